//! Normal and bump maps: the CPU twin of `shaders/lib/surface_map.wgsl`, Mitsuba 3's
//! `normalmap` and `bumpmap` BSDF adapters. Both perturb the shading normal only (the geometric
//! normal keeps deciding sides and ray offsets), in the frame Mitsuba builds at a mesh hit:
//! dp/du of the triangle from its positions and texture coordinates, Gram-Schmidt against the
//! shading normal n (s), and t = n x s.
//!
//! - Normal map (MTL `norm`): the texel, read raw, is 2 rgb - 1 in (s, t, n), normalised.
//! - Bump map (MTL `map_Bump -bm scale`): a height field h = scale x luminance; the surface
//!   p + h n has the tangents dp/du + (dh/du - n.dp/du) n and likewise for v, and its normal
//!   is their cross product, turned to the geometric normal's front side.
//!
//! As Mitsuba's adapters do by default since 3.7.1 (`flip_invalid_normals`,
//! `use_shadowing_function`): a perturbed normal facing away from the viewer has its tangent
//! part negated (Schüssler et al. 2017), and the BSDF's value and sample weight (not its pdf)
//! are multiplied by Conty Estevez et al.'s (2019) terminator shadowing ([`shadowing`]).
//!
//! Mitsuba's two-sided materials (`twosided` around the adapter) mirror the local frame at a
//! back-face hit (the local z flips, x and y stay): the perturbed normal seen from the back is
//! the front one reflected in the tangent plane. The one-sided dielectric sees its negation.

use super::texture::Texture;
use crate::bsdf::frame::basis;
use crate::material::{MATERIAL_DIELECTRIC, Material, NO_TEXTURE, SURFACE_MAP_BUMP};
use glam::{Vec2, Vec3};

/// dp/du and dp/dv of a triangle with corners `p` and texture coordinates `uv` (the
/// parameterisation p(u, v) is affine on it); `None` where the uvs are degenerate (collinear).
pub fn tangents(p: [Vec3; 3], uv: [Vec2; 3]) -> Option<(Vec3, Vec3)> {
    let (dp0, dp1) = (p[1] - p[0], p[2] - p[0]);
    let (duv0, duv1) = (uv[1] - uv[0], uv[2] - uv[0]);
    let det = duv0.x * duv1.y - duv0.y * duv1.x;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    Some((
        (dp0 * duv1.y - dp1 * duv0.y) * inv,
        (dp1 * duv0.x - dp0 * duv1.x) * inv,
    ))
}

/// The shading normal at a hit of a triangle (corners `p`, texture coordinates `uvs`) of
/// material `m` at texture coordinates `uv`: `n` (the unperturbed shading normal, turned to the
/// ray's side) perturbed by the material's map, on the ray's side. `front`: the ray hit the
/// triangle's front (counter-clockwise) face; `wo` toward the viewer. `n` itself when `m` has
/// no map.
#[allow(clippy::too_many_arguments)]
pub fn mapped_normal(
    m: &Material,
    textures: &[Texture],
    p: [Vec3; 3],
    uvs: [Vec2; 3],
    uv: Vec2,
    n: Vec3,
    front: bool,
    wo: Vec3,
) -> Vec3 {
    if m.surface_map == NO_TEXTURE {
        return n;
    }
    let texture = &textures[(m.surface_map & !SURFACE_MAP_BUMP) as usize];
    let sign = if front { 1.0 } else { -1.0 };
    // The front-face frame, as Mitsuba's mesh sees it (its shading normal is not flipped).
    let n0 = n * sign;
    let ng = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
    let (dp_du, dp_dv) = tangents(p, uvs).unwrap_or_else(|| {
        let frame = basis(ng);
        (frame.x_axis, frame.y_axis)
    });
    let perturbed = if m.surface_map & SURFACE_MAP_BUMP == 0 {
        let local = (texture.bilinear(uv).truncate() * 2.0 - Vec3::ONE).normalize();
        let s = (dp_du - n0 * n0.dot(dp_du)).normalize();
        let t = n0.cross(s);
        s * local.x + t * local.y + n0 * local.z
    } else {
        let g = texture.luminance_gradient(uv) * m.bump_scale;
        let du = dp_du + n0 * (g.x - n0.dot(dp_du));
        let dv = dp_dv + n0 * (g.y - n0.dot(dp_dv));
        let nb = du.cross(dv).normalize();
        if nb.dot(ng) < 0.0 { -nb } else { nb }
    };
    let r = if front {
        perturbed
    } else if m.kind == MATERIAL_DIELECTRIC {
        -perturbed
    } else {
        perturbed - 2.0 * perturbed.dot(n0) * n0
    };
    // Facing away from the viewer: the tangent part negated, the part along n kept.
    if n.dot(wo) * r.dot(wo) <= 0.0 {
        2.0 * r.dot(n) * n - r
    } else {
        r
    }
}

/// Conty Estevez et al.'s shadowing of direction `w` by the map's tilt, as Mitsuba's
/// `eval_shadow_terminator`: alpha² = min(tan²(n, ns) / 8, 1), and 2 / (1 + sqrt(1 + alpha²
/// tan²(n, w))); `n` the unperturbed shading normal, `ns` the perturbed one. 1 when equal.
pub fn shadowing(n: Vec3, ns: Vec3, w: Vec3) -> f32 {
    if n == ns {
        return 1.0;
    }
    let tan2 = |c: f32| (1.0 - c * c).max(0.0) / (c * c);
    let alpha2 = (0.125 * tan2(n.dot(ns))).min(1.0);
    2.0 / (1.0 + (1.0 + alpha2 * tan2(n.dot(w))).sqrt())
}

/// Whether a direction `wi` survives the map (Mitsuba's adapters' check): on the same side of
/// the unperturbed shading normal `n` and of the perturbed one `ns`.
pub fn keeps(n: Vec3, ns: Vec3, wi: Vec3) -> bool {
    n.dot(wi) * ns.dot(wi) > 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(rgb: [f32; 3]) -> Texture {
        Texture::from_texels(1, 1, vec![[rgb[0], rgb[1], rgb[2], 1.0]])
    }

    /// The unit square in z = 0, u along x and v along y.
    const P: [Vec3; 3] = [Vec3::ZERO, Vec3::X, Vec3::Y];
    const UV: [Vec2; 3] = [Vec2::ZERO, Vec2::X, Vec2::Y];

    #[test]
    fn tangents_follow_the_texture_coordinates() {
        let (du, dv) = tangents(P, UV).unwrap();
        assert_eq!((du, dv), (Vec3::X, Vec3::Y));
        // u along y, v along -x: both scaled by 2 when the uvs halve.
        let uv = [Vec2::ZERO, Vec2::new(0.0, -0.5), Vec2::new(0.5, 0.0)];
        let (du, dv) = tangents(P, uv).unwrap();
        assert!((du - 2.0 * Vec3::Y).length() < 1e-6 && (dv + 2.0 * Vec3::X).length() < 1e-6);
        assert!(tangents(P, [Vec2::ZERO; 3]).is_none());
    }

    #[test]
    fn a_normal_map_tilts_in_the_tangent_frame_and_mirrors_on_the_back() {
        let m = Material {
            surface_map: 0,
            ..Material::default()
        };
        // (0.75, 0.5, 1): local (0.5, 0, 1), tilted toward +u = +x.
        let textures = [flat([0.75, 0.5, 1.0])];
        let expected = Vec3::new(0.5, 0.0, 1.0).normalize();
        let n = mapped_normal(&m, &textures, P, UV, Vec2::ZERO, Vec3::Z, true, Vec3::Z);
        assert!((n - expected).length() < 1e-6, "{n}");
        let back = mapped_normal(&m, &textures, P, UV, Vec2::ZERO, -Vec3::Z, false, -Vec3::Z);
        assert!(
            (back - Vec3::new(expected.x, 0.0, -expected.z)).length() < 1e-6,
            "{back}"
        );
        let glass = Material {
            kind: MATERIAL_DIELECTRIC,
            ..m
        };
        let back = mapped_normal(
            &glass,
            &textures,
            P,
            UV,
            Vec2::ZERO,
            -Vec3::Z,
            false,
            -Vec3::Z,
        );
        assert!((back + expected).length() < 1e-6, "{back}");
    }

    #[test]
    fn a_normal_facing_away_from_the_viewer_has_its_tangent_part_negated() {
        let m = Material {
            surface_map: 0,
            ..Material::default()
        };
        let textures = [flat([0.75, 0.5, 1.0])];
        // Seen from far toward -x, beyond the tilted normal's horizon.
        let wo = Vec3::new(-1.0, 0.0, 0.1).normalize();
        let n = mapped_normal(&m, &textures, P, UV, Vec2::ZERO, Vec3::Z, true, wo);
        let expected = Vec3::new(-0.5, 0.0, 1.0).normalize();
        assert!((n - expected).length() < 1e-6, "{n}");
    }

    #[test]
    fn shadowing_is_one_overhead_and_falls_toward_the_horizon() {
        let ns = Vec3::new(0.5, 0.0, 1.0).normalize();
        assert_eq!(shadowing(Vec3::Z, Vec3::Z, Vec3::X), 1.0);
        assert!((shadowing(Vec3::Z, ns, Vec3::Z) - 1.0).abs() < 1e-6);
        // tan²(n, ns) = 1/4: alpha² = 1/32; at tan²(w) = 399 (cos 0.05): 2 / (1 + sqrt(13.47)).
        let w = Vec3::new(0.0, (1.0f32 - 0.0025).sqrt(), 0.05);
        let expected = 2.0 / (1.0 + (1.0 + 399.0f32 / 32.0).sqrt());
        assert!((shadowing(Vec3::Z, ns, w) - expected).abs() < 1e-4);
    }

    #[test]
    fn a_bump_map_of_a_ramp_tilts_against_its_slope() {
        // h = scale x (texel x / 4): along u the height rises by 1/4 per texel of 1/4 in u,
        // a slope of 1 (times the scale 0.5); the normal of z = 0.5 x is (-0.5, 0, 1).
        let texels = (0..4)
            .flat_map(|_| (0..4).map(|x| [x as f32 / 4.0; 4]))
            .collect();
        let textures = [Texture::from_texels(4, 4, texels)];
        let m = Material {
            surface_map: SURFACE_MAP_BUMP,
            bump_scale: 0.5,
            ..Material::default()
        };
        let n = mapped_normal(
            &m,
            &textures,
            P,
            UV,
            Vec2::new(0.4, 0.3),
            Vec3::Z,
            true,
            Vec3::Z,
        );
        let expected = Vec3::new(-0.5, 0.0, 1.0).normalize();
        assert!((n - expected).length() < 1e-5, "{n}");
    }
}
