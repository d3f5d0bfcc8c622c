//! Dense pencils (K, M) with known eigenvalues and a super-element's spectrum, for the dense
//! CEA's check (`tests/numerics/cea.rs`) and its benchmark (`examples/dense_cea_bench.rs`,
//! which includes this file by path).

use faer::Mat;
use num_complex::Complex64;
use std::f64::consts::PI;

/// Size n (even): frequencies evenly from 300 Hz to 300 kHz, as a super-element's reach the
/// hundreds of kHz of its stiffest boundary coordinates, so that 0-10 kHz holds a few per
/// cent of them. K = L Q A Q^T L^T, M = L L^T, with A block-diagonal (block b holds omega^2
/// = k_b (1 +/- 0.004 i) on two of every three blocks, a double real k_b on the third), Q
/// orthogonal and L lower triangular, both full (a fixed pseudo-random seed): the
/// eigenvalues omega^2 of (K, M) are A's, returned beside.
pub fn super_element_pencil(n: usize) -> (Mat<f64>, Mat<f64>, Vec<Complex64>) {
    super_element_pencil_with(n, &[])
}

/// [`super_element_pencil`] with block b's k_b set to the given omega^2 for each (b, omega^2)
/// of `placed`: eigenvalues put where a test wants them (on an edge between windows).
pub fn super_element_pencil_with(
    n: usize,
    placed: &[(usize, f64)],
) -> (Mat<f64>, Mat<f64>, Vec<Complex64>) {
    let mut seed = 0x5eed_u64;
    let mut random = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let blocks = n / 2;
    let kk = |b: usize| {
        placed.iter().find(|p| p.0 == b).map_or_else(
            || (2.0 * PI * (300.0 + 300_000.0 * b as f64 / blocks as f64)).powi(2),
            |p| p.1,
        )
    };
    let cc = |b: usize| if b % 3 == 2 { 0.0 } else { 0.004 * kk(b) };
    let mut a = Mat::<f64>::zeros(n, n);
    let mut exact = Vec::with_capacity(n);
    for b in 0..blocks {
        let (i, j) = (2 * b, 2 * b + 1);
        a[(i, i)] = kk(b);
        a[(j, j)] = kk(b);
        a[(i, j)] = cc(b);
        a[(j, i)] = -cc(b);
        exact.push(Complex64::new(kk(b), cc(b)));
        exact.push(Complex64::new(kk(b), -cc(b)));
    }
    let q = Mat::<f64>::from_fn(n, n, |_, _| random()).qr().compute_Q();
    let l = Mat::<f64>::from_fn(n, n, |i, j| match i.cmp(&j) {
        std::cmp::Ordering::Equal => 1.0 + 0.5 * random().abs(),
        std::cmp::Ordering::Greater => 0.2 * random() / (n as f64).sqrt(),
        std::cmp::Ordering::Less => 0.0,
    });
    let lq = &l * &q;
    (&lq * &a * lq.transpose(), &l * l.transpose(), exact)
}
