//! Quadrature for the tables the models precompute.

use std::f64::consts::PI;

/// Nodes and weights of the n-point Gauss-Legendre rule on [-1, 1] (Newton on P_n from
/// Chebyshev guesses, as Mitsuba's `quad::gauss_legendre`).
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = vec![0.0; n];
    let mut weights = vec![0.0; n];
    for i in 0..n.div_ceil(2) {
        let mut x = -((2 * i + 1) as f64 / (2 * n) as f64 * PI).cos();
        for _ in 0..100 {
            let (p, dp) = legendre_pd(n, x);
            let step = p / dp;
            x -= step;
            if step.abs() <= 4.0 * x.abs() * f64::EPSILON {
                break;
            }
        }
        let (_, dp) = legendre_pd(n, x);
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        nodes[i] = x;
        nodes[n - 1 - i] = -x;
        weights[i] = w;
        weights[n - 1 - i] = w;
    }
    (nodes, weights)
}

/// P_n(x) and its derivative, by the three-term recurrence.
fn legendre_pd(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 1..n {
        let p2 = ((2 * k + 1) as f64 * x * p1 - k as f64 * p0) / (k + 1) as f64;
        p0 = p1;
        p1 = p2;
    }
    let dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, dp)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rule integrates polynomials of degree 2n - 1 exactly: a wrong node or weight fails.
    #[test]
    fn gauss_legendre_is_exact_for_polynomials_of_degree_2n_minus_1() {
        for n in [1usize, 2, 5, 32, 128] {
            let (x, w) = gauss_legendre(n);
            for k in 0..2 * n {
                let q: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(k as i32)).sum();
                let exact = if k % 2 == 1 {
                    0.0
                } else {
                    2.0 / (k + 1) as f64
                };
                assert!(
                    (q - exact).abs() < 1e-12,
                    "n {n} degree {k}: {q} vs {exact}"
                );
            }
        }
    }
}
