//! Which contact pair feeds an unstable mode: its growth rate split over the pairs, from the
//! mode's own shape (issue 33).
//!
//! For a mode (lambda^2 M + lambda C + K_t) x = 0 with lambda = a + i omega, premultiplying by
//! x^H gives lambda^2 m + lambda c + k = 0 with m = x^H M x and c = x^H C x real (M, C
//! symmetric) and k = x^H K_t x. Its imaginary part is 2 a omega m + omega c + Im k = 0, so
//!
//!   a = -Im(x^H K_t x) / (2 omega m) - c / (2 m).
//!
//! The structure's stiffness, springs and ties are symmetric and give a real x^H K x: only
//! the contact pairs' unsymmetric tangents (friction, and the geometry of node-to-surface
//! contact) give Im k, and Im(x^H J x) = Re(x)^T (J - J^T) Im(x) for a real block J. So each
//! pair's points give a_p = -Im(x^H J_p x) / (2 omega m) and the a_p add up to the growth
//! rate (less the damping's -c / 2m): the work the pair's forces do on the mode per cycle,
//! over twice its energy. This is an identity of the eigenpair, not an estimate: the sum is
//! checked against the CEA's own real part. A pair's a_p is negative where it takes energy
//! out of the mode.

use crate::contact::{self, ContactError, ContactPair, SlipHistory};
use std::collections::BTreeMap;

/// Im(x^H J x) for one point's contribution, with the shape's real and imaginary parts at
/// every node of the model.
fn imaginary_part(c: &contact::PointContribution, re: &[[f64; 3]], im: &[[f64; 3]]) -> f64 {
    let width = 3 * c.nodes.len();
    let at = |field: &[[f64; 3]], k: usize| field[c.nodes[k / 3]][k % 3];
    let mut sum = 0.0;
    for i in 0..width {
        for j in 0..width {
            let skew = c.jacobian[i * width + j] - c.jacobian[j * width + i];
            sum += at(re, i) * skew * at(im, j);
        }
    }
    sum
}

/// A mode's shape at every node of the model (extra nodes included): real and imaginary
/// parts.
#[derive(Clone, Copy, Debug)]
pub struct Shape<'a> {
    pub re: &'a [[f64; 3]],
    pub im: &'a [[f64; 3]],
}

/// Each contact point's part of the growth rate, a_k = -Im(x^H J_k x) / (2 omega m) (1/s),
/// per pair in the model's order, with the contact tangent of a CEA about `u`
/// ([`crate::analysis::statics::add_perturbation_tangent`]: the committed history `after`);
/// `omega` is Im(lambda) (rad/s) and `modal_mass` x^H M x. An open point's part is 0.
pub fn point_growth_rates(
    pairs: &[ContactPair],
    after: &SlipHistory,
    u: &[[f64; 3]],
    shape: Shape<'_>,
    omega: f64,
    modal_mass: f64,
) -> Result<Vec<Vec<f64>>, ContactError> {
    let history = contact::perturbation_history(pairs, after);
    let scale = -1.0 / (2.0 * omega * modal_mass);
    let mut rates = Vec::with_capacity(pairs.len());
    for (i, pair) in pairs.iter().enumerate() {
        let mut of_pair = Vec::with_capacity(pair.points.len());
        for (k, point) in pair.points.iter().enumerate() {
            let (state, contribution) = contact::evaluate(pair, point, history.anchor(i, k), u)?;
            let mut sum = 0.0;
            if let Some(c) = contribution {
                sum += imaginary_part(&c, shape.re, shape.im);
            }
            // CalculiX's perturbation tangent adds a stick slope across the sliding.
            if let Some(c) = contact::variant::across_sliding(pair, point, &state) {
                sum += imaginary_part(&c, shape.re, shape.im);
            }
            of_pair.push(scale * sum);
        }
        rates.push(of_pair);
    }
    Ok(rates)
}

/// Each pair's part of the growth rate, a_p = sum of its points' [`point_growth_rates`], by
/// name (pairs named twice are summed under their name).
pub fn pair_growth_rates(pairs: &[ContactPair], points: &[Vec<f64>]) -> BTreeMap<String, f64> {
    let mut rates = BTreeMap::new();
    for (pair, of_pair) in pairs.iter().zip(points) {
        *rates.entry(pair.settings.name.clone()).or_insert(0.0) += of_pair.iter().sum::<f64>();
    }
    rates
}

/// The rates as shares of their sum (summing to 1); empty when the sum is 0. A pair that
/// takes energy out of the mode has a negative share, and the others then add up to more
/// than 1.
pub fn shares(rates: &BTreeMap<String, f64>) -> BTreeMap<String, f64> {
    let total: f64 = rates.values().sum();
    if total == 0.0 {
        return BTreeMap::new();
    }
    rates
        .iter()
        .map(|(name, a)| (name.clone(), a / total))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Im(x^H J x) of a spelt-out 2-node block against the complex product computed term by
    /// term.
    #[test]
    fn the_imaginary_part_is_that_of_the_complex_product() {
        let jacobian: Vec<f64> = (0..36).map(|k| ((k * 7) % 11) as f64 - 5.0).collect();
        let c = contact::PointContribution {
            nodes: vec![1, 0],
            residual: vec![0.0; 6],
            jacobian: jacobian.clone(),
        };
        let re = [[0.3, -1.0, 2.0], [0.5, 0.25, -0.75]];
        let im = [[1.5, 0.0, -0.5], [-2.0, 1.0, 0.125]];
        let x: Vec<num_complex::Complex64> = (0..6)
            .map(|k| {
                let node = c.nodes[k / 3];
                num_complex::Complex64::new(re[node][k % 3], im[node][k % 3])
            })
            .collect();
        let mut product = num_complex::Complex64::new(0.0, 0.0);
        for i in 0..6 {
            for j in 0..6 {
                product += x[i].conj() * jacobian[i * 6 + j] * x[j];
            }
        }
        let got = imaginary_part(&c, &re, &im);
        assert!(
            (got - product.im).abs() <= 1e-12 * product.im.abs(),
            "{got} {product}"
        );
    }
}
