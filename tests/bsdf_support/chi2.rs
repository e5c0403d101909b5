//! Pearson's chi-square test of sampled directions against a density, as Mitsuba 3's `chi2`
//! and pbrt's tests run it: cells with low expected counts are pooled, and the p-value comes
//! from the chi-square distribution's survival function.

/// The outcome of one test: the statistic, its degrees of freedom and the p-value.
#[derive(Debug, Clone, Copy)]
pub struct Chi2 {
    pub statistic: f64,
    pub dof: usize,
    pub p_value: f64,
}

/// Observed against expected counts (same length, same total up to the density's integration
/// error); cells expecting fewer than 5 are pooled into one.
pub fn chi2_test(observed: &[f64], expected: &[f64]) -> Chi2 {
    let mut cells: Vec<(f64, f64)> = Vec::new();
    let (mut pool_o, mut pool_e) = (0.0, 0.0);
    for (&o, &e) in observed.iter().zip(expected) {
        if e < 5.0 {
            pool_o += o;
            pool_e += e;
        } else {
            cells.push((o, e));
        }
    }
    if pool_e >= 5.0 || (pool_e > 0.0 && cells.is_empty()) {
        cells.push((pool_o, pool_e));
    } else if pool_e > 0.0 || pool_o > 0.0 {
        // Too small a pool for the statistic's approximation: fold it into the smallest cell.
        let smallest = cells
            .iter_mut()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .expect("some cell");
        smallest.0 += pool_o;
        smallest.1 += pool_e;
    }
    let statistic: f64 = cells.iter().map(|(o, e)| (o - e) * (o - e) / e).sum();
    let dof = cells.len().saturating_sub(1).max(1);
    Chi2 {
        statistic,
        dof,
        p_value: gamma_q(dof as f64 / 2.0, statistic / 2.0),
    }
}

/// ln Gamma(x), Lanczos (g = 7, 9 terms), x > 0.
fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + 7.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The regularised upper incomplete gamma function Q(a, x): the series below a + 1, Lentz's
/// continued fraction above.
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let gln = ln_gamma(a);
    if x < a + 1.0 {
        let (mut ap, mut sum) = (a, 1.0 / a);
        let mut del = sum;
        for _ in 0..10_000 {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if del.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        1.0 - sum * (-x + a * x.ln() - gln).exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-15 {
                break;
            }
        }
        (-x + a * x.ln() - gln).exp() * h
    }
}
