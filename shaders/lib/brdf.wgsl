// Normalised Blinn-Phong: f = kd / pi + ks (ns + 8) / (8 pi) max(0, n.h)^ns.

fn brdf(m: Material, n: vec3<f32>, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    var f = m.kd * (1.0 / PI);
    // Specialised away when no material of the scene has a specular lobe.
    if scene_has_specular {
        let h = normalize(wo + wi);
        let lobe = (m.ns + 8.0) / (8.0 * PI) * pow(max(0.0, dot(n, h)), m.ns);
        f += m.ks * lobe;
    }
    return f;
}
