//! `<spectrum>` values as Mitsuba 3's RGB variants turn them into colours (checked against pip
//! Mitsuba 3.9.0 in tests/mitsuba_xml.rs):
//!
//! - one number v: a uniform spectrum. Outside an emitter it is the grey v. Inside one it is
//!   the equal-energy white of luminance v, the XYZ colour (v, v, v) in linear sRGB (about
//!   1.205 v, 0.948 v, 0.909 v).
//! - `wavelength:value` pairs: the piecewise linear spectrum between the first and last
//!   wavelength (zero outside), integrated against the CIE 1931 matching functions at 1000
//!   points evenly spaced over 360-830 nm (a point's weight 470/1000 nm), scaled so that a unit
//!   spectrum has luminance 1, and taken to linear sRGB with Mitsuba's XYZ -> sRGB matrix
//!   (`spectrum_list_to_srgb`). A reflectance (outside an emitter) is weighted by the D65
//!   illuminant, so that a flat reflectance stays grey, and clamped to [0, 1]; an emission
//!   spectrum is not weighted, and only negative values are clamped.
//!
//! Spectra from files (`filename`) and blackbody spectra are not supported.

use super::cie::{CIE_D65, CIE_MAX, CIE_MIN, CIE_SAMPLES, CIE_XYZ};

/// Mitsuba's MI_CIE_Y_NORMALIZATION: a unit spectrum integrates to luminance 1.
const CIE_Y_NORMALIZATION: f64 = 1.0 / 106.750_259_399_414_06;

/// Mitsuba's `xyz_to_srgb` matrix, row-major.
const XYZ_TO_SRGB: [[f64; 3]; 3] = [
    [3.240479, -1.537150, -0.498535],
    [-0.969256, 1.875991, 0.041556],
    [0.055648, -0.204043, 1.057311],
];

/// The number of integration points of `spectrum_list_to_srgb`.
const STEPS: usize = 1000;

/// Linear interpolation in a table sampled every 5 nm from CIE_MIN (as Mitsuba's
/// `cie1931_xyz` and `cie_d65`): zero outside [CIE_MIN, CIE_MAX].
fn table_at<const N: usize>(table: &[[f64; N]; CIE_SAMPLES], wavelength: f64) -> [f64; N] {
    if !(CIE_MIN..=CIE_MAX).contains(&wavelength) {
        return [0.0; N];
    }
    let t = (wavelength - CIE_MIN) * ((CIE_SAMPLES - 1) as f64 / (CIE_MAX - CIE_MIN));
    let i0 = (t as usize).min(CIE_SAMPLES - 2);
    let w1 = t - i0 as f64;
    let w0 = 1.0 - w1;
    std::array::from_fn(|c| w0 * table[i0][c] + w1 * table[i0 + 1][c])
}

/// The CIE 1931 matching functions at `wavelength` (nm), as Mitsuba's `cie1931_xyz`.
pub fn cie1931_xyz(wavelength: f64) -> [f64; 3] {
    table_at(&CIE_XYZ, wavelength)
}

/// The D65 illuminant at `wavelength` (nm), as Mitsuba's `cie_d65`.
pub fn cie_d65(wavelength: f64) -> f64 {
    let table: [[f64; 1]; CIE_SAMPLES] = std::array::from_fn(|i| [CIE_D65[i]]);
    table_at(&table, wavelength)[0]
}

pub fn xyz_to_srgb(xyz: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|r| (0..3).map(|c| XYZ_TO_SRGB[r][c] * xyz[c]).sum())
}

/// Mitsuba's `spectrum_list_to_srgb(wavelengths, values, bounded, d65)`. `wavelengths` must
/// be increasing with at least two entries (the parser checks).
pub fn spectrum_list_to_srgb(
    wavelengths: &[f64],
    values: &[f64],
    bounded: bool,
    d65: bool,
) -> [f64; 3] {
    let (first, last) = (wavelengths[0], wavelengths[wavelengths.len() - 1]);
    let mut xyz = [0.0f64; 3];
    for i in 0..STEPS {
        let x = CIE_MIN + (i as f64 / (STEPS - 1) as f64) * (CIE_MAX - CIE_MIN);
        if x < first || x > last {
            continue;
        }
        // The interval [w[k], w[k + 1]] holding x (the last one for x == last).
        let k = wavelengths
            .partition_point(|&w| w <= x)
            .saturating_sub(1)
            .min(wavelengths.len() - 2);
        let (x0, x1, y0, y1) = (wavelengths[k], wavelengths[k + 1], values[k], values[k + 1]);
        let y = (x * y0 - x1 * y0 - x * y1 + x0 * y1) / (x0 - x1);
        let mut cmf = cie1931_xyz(x);
        if d65 {
            let d = cie_d65(x);
            cmf = cmf.map(|c| c * d);
        }
        for c in 0..3 {
            xyz[c] += cmf[c] * y;
        }
    }
    let scale = (CIE_MAX - CIE_MIN) / STEPS as f64 * CIE_Y_NORMALIZATION;
    let rgb = xyz_to_srgb(xyz.map(|c| c * scale));
    rgb.map(|c| {
        if bounded {
            c.clamp(0.0, 1.0)
        } else {
            c.max(0.0)
        }
    })
}

/// A `<spectrum value>` as the colour Mitsuba's RGB variants make of it; `in_emitter`: the
/// property belongs to an emitter (a radiance, intensity or irradiance).
pub fn spectrum_to_rgb(spectrum: &SpectrumValue, in_emitter: bool) -> [f64; 3] {
    match spectrum {
        SpectrumValue::Uniform(v) => {
            if in_emitter {
                // Mitsuba takes a flat emission spectrum as the XYZ colour (v, v, v).
                xyz_to_srgb([*v; 3])
            } else {
                [*v; 3]
            }
        }
        SpectrumValue::List {
            wavelengths,
            values,
        } => spectrum_list_to_srgb(wavelengths, values, !in_emitter, !in_emitter),
    }
}

/// A parsed `<spectrum value>`.
#[derive(Clone, Debug, PartialEq)]
pub enum SpectrumValue {
    Uniform(f64),
    List {
        wavelengths: Vec<f64>,
        values: Vec<f64>,
    },
}

/// `"0.5"` or `"400:0.1, 500:0.2, ..."` (increasing wavelengths, at least two pairs).
pub fn parse_spectrum(text: &str) -> Result<SpectrumValue, String> {
    let text = text.trim();
    if !text.contains(':') {
        return text
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .map(SpectrumValue::Uniform)
            .ok_or_else(|| format!("'{text}' is neither a number nor wavelength:value pairs"));
    }
    let mut wavelengths = Vec::new();
    let mut values = Vec::new();
    for pair in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (w, v) = pair
            .split_once(':')
            .ok_or_else(|| format!("'{pair}' is not a wavelength:value pair"))?;
        let number = |s: &str| {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("'{}' in '{pair}' is not a finite number", s.trim()))
        };
        let (w, v) = (number(w)?, number(v)?);
        if wavelengths.last().is_some_and(|&last| w <= last) {
            return Err(format!(
                "wavelengths must increase: {w} follows {}",
                wavelengths[wavelengths.len() - 1]
            ));
        }
        wavelengths.push(w);
        values.push(v);
    }
    if wavelengths.len() < 2 {
        return Err("a spectrum of wavelength:value pairs needs at least two".into());
    }
    Ok(SpectrumValue::List {
        wavelengths,
        values,
    })
}
