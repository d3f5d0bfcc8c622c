//! Independent reference solutions for the modal-analysis verification tests.
//!
//! Everything here is computed from the classical analytical theory with nothing but `std`,
//! so it shares no code (and no modelling shortcut) with the finite-element solver it checks:
//!
//! * [`cantilever_euler_bernoulli`]: bending of a clamped-free Euler–Bernoulli beam;
//! * [`cantilever_timoshenko`]: the same with shear flexibility and rotary inertia (exact
//!   Timoshenko frequency equation, Cowper's shear coefficient);
//! * [`cantilever_torsion_saint_venant`]: torsion of a clamped-free bar of rectangular section;
//! * [`annular_plate_clamped_free`]: Kirchhoff annular plate clamped at the hole, free outside
//!   (the classical idealisation of a brake disc), with the Bessel functions
//!   [`bessel_jy`], [`bessel_ik`] implemented here.
//!
//! All frequencies are returned in Hz, in increasing order, for SI (or any consistent) units.
#![allow(dead_code)]

use std::f64::consts::PI;

/// Euler–Mascheroni constant γ.
const EULER_GAMMA: f64 = 0.577_215_664_901_532_9;

// ---------------------------------------------------------------------------------------------
// Root finding and small dense determinants
// ---------------------------------------------------------------------------------------------

/// Bisection of `f` on `[a, b]` where `f(a)` (given as `fa`) and `f(b)` differ in sign
/// (negative versus non-negative); runs until the bracket cannot shrink any more.
fn bisect(f: &impl Fn(f64) -> f64, mut a: f64, mut b: f64, mut fa: f64) -> f64 {
    for _ in 0..2000 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        let fm = f(m);
        if (fm < 0.0) == (fa < 0.0) {
            a = m;
            fa = fm;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

/// The first `count` sign changes of `f` above `start`, scanning with the step `step(x)` and
/// refining each bracket by bisection. Panics past `limit` (no silent infinite loop).
///
/// `f` must be continuous (no poles), so every sign change is a root; the step must be smaller
/// than the spacing of the roots, or two of them could hide in one step.
fn scan_roots(
    f: impl Fn(f64) -> f64,
    start: f64,
    step: impl Fn(f64) -> f64,
    count: usize,
    limit: f64,
) -> Vec<f64> {
    let mut roots = Vec::with_capacity(count);
    let mut x0 = start;
    let mut f0 = f(x0);
    assert!(f0.is_finite(), "characteristic function not finite at {x0}");
    while roots.len() < count {
        assert!(
            x0 < limit,
            "root scan reached {limit} with only {} of {count} roots",
            roots.len()
        );
        let x1 = x0 + step(x0);
        let f1 = f(x1);
        assert!(f1.is_finite(), "characteristic function not finite at {x1}");
        if (f0 < 0.0) != (f1 < 0.0) {
            roots.push(bisect(&f, x0, x1, f0));
        }
        x0 = x1;
        f0 = f1;
    }
    roots
}

/// Determinant by Gaussian elimination with partial pivoting (sign exact up to rounding).
fn determinant<const N: usize>(mut a: [[f64; N]; N]) -> f64 {
    let mut det = 1.0;
    for col in 0..N {
        let pivot = (col..N)
            .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
            .unwrap_or(col);
        if a[pivot][col] == 0.0 {
            return 0.0;
        }
        if pivot != col {
            a.swap(pivot, col);
            det = -det;
        }
        det *= a[col][col];
        let pivot_row = a[col];
        for row in a.iter_mut().skip(col + 1) {
            let factor = row[col] / pivot_row[col];
            for (v, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                *v -= factor * p;
            }
        }
    }
    det
}

// ---------------------------------------------------------------------------------------------
// Euler–Bernoulli cantilever
// ---------------------------------------------------------------------------------------------

/// The first `count` roots `βₙL` of the clamped-free frequency equation `1 + cos x cosh x = 0`.
///
/// Solved as `cos x + 1/cosh x = 0` (no overflow), whose n-th root is the only one in
/// `[(n-1)π, nπ]`, by bisection to machine precision. Known values: 1.875104068712,
/// 4.694091132974, 7.854757438238, 10.995540734875, then → (2n-1)π/2.
pub fn clamped_free_beam_roots(count: usize) -> Vec<f64> {
    let f = |x: f64| x.cos() + 1.0 / x.cosh();
    (1..=count)
        .map(|n| {
            let a = (n - 1) as f64 * PI;
            let b = n as f64 * PI;
            debug_assert!(f(a) * f(b) < 0.0);
            bisect(&f, a, b, f(a))
        })
        .collect()
}

/// Bending natural frequencies (Hz) of a clamped-free Euler–Bernoulli beam:
///
/// `fₙ = (βₙL)² / (2π L²) · √(E I / (ρ A))`, with `βₙL` the roots of `1 + cos βL cosh βL = 0`
/// ([`clamped_free_beam_roots`]); e.g. Blevins, *Formulas for Natural Frequency and Mode
/// Shape* (1979), ch. 8; Timoshenko, Young & Weaver, *Vibration Problems in Engineering*.
/// Shear deformation and rotary inertia are neglected (see [`cantilever_timoshenko`]).
pub fn cantilever_euler_bernoulli(
    length: f64,
    young: f64,
    density: f64,
    area: f64,
    second_moment: f64,
    count: usize,
) -> Vec<f64> {
    let c = (young * second_moment / (density * area)).sqrt();
    clamped_free_beam_roots(count)
        .into_iter()
        .map(|bl| bl * bl / (2.0 * PI * length * length) * c)
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Timoshenko cantilever
// ---------------------------------------------------------------------------------------------

/// Which principal axis of the `width` × `height` rectangle the beam bends about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BendingAxis {
    /// Neutral axis parallel to the `width` side: the beam deflects along `height`,
    /// `I = width·height³/12`.
    Width,
    /// Neutral axis parallel to the `height` side: the beam deflects along `width`,
    /// `I = height·width³/12`.
    Height,
}

/// Cowper's shear coefficient of a rectangular section, `k = 10(1+ν)/(12+11ν)`
/// (G. R. Cowper, "The shear coefficient in Timoshenko's beam theory",
/// J. Appl. Mech. 33 (1966) 335–340). 0.8497 for ν = 0.3; 5/6 for ν = 0.
pub fn cowper_shear_coefficient_rectangle(poisson: f64) -> f64 {
    10.0 * (1.0 + poisson) / (12.0 + 11.0 * poisson)
}

/// Bending natural frequencies (Hz) of a clamped-free Timoshenko beam of rectangular section
/// `width` × `height`, isotropic (`G = E/(2(1+ν))`), shear coefficient from
/// [`cowper_shear_coefficient_rectangle`], bending about `bending_axis`.
///
/// Solves the exact frequency equation of Timoshenko's theory (S. P. Timoshenko, Phil. Mag. 41
/// (1921) 744; for the clamped-free case e.g. Huang, J. Appl. Mech. 28 (1961) 579), see
/// [`timoshenko_clamped_free_omegas`] for the formulation; valid below and above the
/// critical frequency `√(kGA/(ρI))` (the "second spectrum").
#[allow(clippy::too_many_arguments)]
pub fn cantilever_timoshenko(
    length: f64,
    young: f64,
    poisson: f64,
    density: f64,
    width: f64,
    height: f64,
    count: usize,
    bending_axis: BendingAxis,
) -> Vec<f64> {
    let area = width * height;
    let second_moment = match bending_axis {
        BendingAxis::Width => width * height.powi(3) / 12.0,
        BendingAxis::Height => height * width.powi(3) / 12.0,
    };
    let shear_modulus = young / (2.0 * (1.0 + poisson));
    let k = cowper_shear_coefficient_rectangle(poisson);
    timoshenko_clamped_free_omegas(
        length,
        young * second_moment,
        k * shear_modulus * area,
        density * area,
        density * second_moment,
        count,
    )
    .into_iter()
    .map(|w| w / (2.0 * PI))
    .collect()
}

/// `(C, S) = (cosh(√p x), sinh(√p x)/√p)` continued analytically to `p ≤ 0`
/// (`cos(√-p x)`, `sin(√-p x)/√-p`; `1`, `x` at `p = 0`): entire functions of `p`,
/// with `C' = p S`, `S' = C`.
fn cosh_sinh_entire(p: f64, x: f64) -> (f64, f64) {
    if p > 0.0 {
        let s = p.sqrt();
        ((s * x).cosh(), (s * x).sinh() / s)
    } else if p < 0.0 {
        let s = (-p).sqrt();
        ((s * x).cos(), (s * x).sin() / s)
    } else {
        (1.0, x)
    }
}

/// Circular natural frequencies (rad/s) of a clamped(x=0)-free(x=L) Timoshenko beam with
/// bending stiffness `ei`, shear stiffness `kga`, mass per length `rho_a`, rotary inertia per
/// length `rho_i`.
///
/// Equations of motion (deflection `w`, section rotation `ψ`):
/// `kGA (w'' − ψ') = ρA ẅ`, `EI ψ'' + kGA (w' − ψ) = ρI ψ̈`. With `e^{iωt}` and `w ∝ e^{sx}`,
/// `p = s²` solves `p² + ω²(ρI/EI + ρA/kGA) p + (ρAω²/EI)(ρIω²/kGA − 1) = 0`: two real roots,
/// `p₂ < 0` always and `p₁ > 0` below, `< 0` above the critical frequency `√(kGA/ρI)`.
/// With `q = ρAω²/kGA` and `(C, S)` of `cosh_sinh_entire`, each root gives the two solutions
/// `(w, ψ) = (C, (p+q) S)` and `(p S, (p+q) C)` (ψ' = w'' + q w), continuous through the
/// critical frequency. The conditions `w(0) = ψ(0) = 0`, `ψ'(L) = 0` (moment) and
/// `w'(L) − ψ(L) = 0` (shear) give a 4×4 determinant, entire in ω, whose roots are found by a
/// scan (phase step ≤ 0.05 rad) and bisection.
pub fn timoshenko_clamped_free_omegas(
    length: f64,
    ei: f64,
    kga: f64,
    rho_a: f64,
    rho_i: f64,
    count: usize,
) -> Vec<f64> {
    let wave_numbers = |omega: f64| {
        let w2 = omega * omega;
        let b = w2 * (rho_i / ei + rho_a / kga);
        let c = rho_a * w2 / ei * (rho_i * w2 / kga - 1.0);
        let p2 = -0.5 * (b + (b * b - 4.0 * c).sqrt());
        (c / p2, p2)
    };
    let det = |omega: f64| {
        let (p1, p2) = wave_numbers(omega);
        let q = rho_a * omega * omega / kga;
        let (c1, s1) = cosh_sinh_entire(p1, length);
        let (c2, s2) = cosh_sinh_entire(p2, length);
        // Rows at x = L scaled by a positive factor (the growth of cosh) to stay O(1).
        let g = 1.0 / c1.abs().max(1.0);
        let m = [
            [1.0, 0.0, 1.0, 0.0],
            [0.0, p1 + q, 0.0, p2 + q],
            [
                g * (p1 + q) * c1,
                g * (p1 + q) * p1 * s1,
                g * (p2 + q) * c2,
                g * (p2 + q) * p2 * s2,
            ],
            // (w' − ψ)(L) divided by −q.
            [g * s1, g * c1, g * s2, g * c2],
        ];
        determinant(m)
    };
    let omega_ref = (ei / rho_a).sqrt() / (length * length);
    let step = |omega: f64| {
        let (p1, p2) = wave_numbers(omega);
        let phase = length * p1.abs().sqrt().max(p2.abs().sqrt());
        omega * 0.05 / phase.max(1.0)
    };
    scan_roots(det, 0.05 * omega_ref, step, count, 1e12 * omega_ref)
}

// ---------------------------------------------------------------------------------------------
// Saint-Venant torsion
// ---------------------------------------------------------------------------------------------

/// Saint-Venant torsion constant of a `width` × `height` rectangle: with `a ≥ b` the long and
/// short sides,
///
/// `J = a b³/3 · [1 − (192/π⁵)(b/a) Σ_{n=1,3,5,…} tanh(nπa/(2b))/n⁵]`
///
/// (Timoshenko & Goodier, *Theory of Elasticity*, 3rd ed., §109). The series is summed to
/// n = 19999 plus the tail `Σ_{n>N} n⁻⁵ ≈ 1/(8(N+1)⁴)` (tanh = 1 there), i.e. to rounding.
/// `J/(a b³)` = 0.1406 (square), 0.2287 (a/b = 2), 0.3123 (a/b = 10), → 1/3.
pub fn saint_venant_torsion_constant_rectangle(width: f64, height: f64) -> f64 {
    let (a, b) = if width >= height {
        (width, height)
    } else {
        (height, width)
    };
    const LAST: usize = 19_999;
    let mut sum = 1.0 / (8.0 * ((LAST + 1) as f64).powi(4));
    // Small terms first.
    for n in (1..=LAST).rev().step_by(2) {
        let nf = n as f64;
        sum += (nf * PI * a / (2.0 * b)).tanh() / nf.powi(5);
    }
    a * b.powi(3) / 3.0 * (1.0 - 192.0 / PI.powi(5) * (b / a) * sum)
}

/// Torsional natural frequencies (Hz) of a clamped-free bar of rectangular section
/// `width` × `height` in Saint-Venant torsion:
///
/// `fₙ = (2n − 1)/(4L) · √(G J / (ρ I_p))`, `I_p = width·height·(width² + height²)/12`,
///
/// with `J` from [`saint_venant_torsion_constant_rectangle`] (the wave equation
/// `G J θ'' = ρ I_p θ̈`, θ(0) = 0, θ'(L) = 0; e.g. Blevins (1979), ch. 8). Warping
/// restraint at the clamp (Vlasov) and the rotary inertia of warping are neglected: the
/// finite-element model of a short, wide bar will be somewhat stiffer than this.
pub fn cantilever_torsion_saint_venant(
    length: f64,
    shear_modulus: f64,
    density: f64,
    width: f64,
    height: f64,
    count: usize,
) -> Vec<f64> {
    let j = saint_venant_torsion_constant_rectangle(width, height);
    let polar = width * height * (width * width + height * height) / 12.0;
    let c = (shear_modulus * j / (density * polar)).sqrt();
    (1..=count)
        .map(|n| (2 * n - 1) as f64 / (4.0 * length) * c)
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Bessel functions of integer order
// ---------------------------------------------------------------------------------------------

/// Even start index of Miller's backward recurrence for orders up to `n_max` at `x`
/// (generous: the neglected tail is far below rounding for x up to several thousand).
fn miller_start(n_max: usize, x: f64) -> usize {
    let big = (n_max as f64).max(x);
    let m = (big + 20.0 + (160.0 * big).sqrt()).ceil() as usize;
    (m.max(n_max + 2) + 1) & !1
}

/// Backward recurrence `f_{k−1} = (2k/x) f_k + sign·f_{k+1}` from `f_m = 1`, `f_{m+1} = 0`,
/// rescaled on the fly against overflow; returns `f_0 … f_{m+1}` (arbitrary common scale).
fn miller_backward(m: usize, x: f64, sign: f64) -> Vec<f64> {
    let mut f = vec![0.0; m + 2];
    f[m] = 1.0;
    for k in (1..=m).rev() {
        let v = 2.0 * k as f64 / x * f[k] + sign * f[k + 1];
        f[k - 1] = v;
        if v.abs() > 1e250 {
            for g in &mut f[k - 1..] {
                *g *= 1e-250;
            }
        }
    }
    f
}

/// `J_k(x)` and `Y_k(x)` for `k = 0 … n_max`, `x > 0`.
///
/// `J_k`: Miller's backward recurrence normalised by `J₀ + 2 Σ J_{2k} = 1` (Abramowitz &
/// Stegun 9.1.46), stable for all k and x. `Y₀`, `Y₁`: Neumann series (A&S 9.1.88 for Y₀;
/// both as in Zhang & Jin, *Computation of Special Functions*, 1996, routine JYNB)
/// `π/2 Y₀ = (ln(x/2)+γ) J₀ − 2 Σ_{k≥1} (−1)^k J_{2k}/k`,
/// `π/2 Y₁ = (ln(x/2)+γ−1) J₁ − J₀/x − 4 Σ_{k≥1} (−1)^k (2k+1)/(4k(k+1)) J_{2k+1}`;
/// then the (stable) forward recurrence `Y_{k+1} = (2k/x) Y_k − Y_{k−1}`.
/// Accuracy about 1e-14 relative to the envelope (absolute near zeros) for x ≲ 1000.
pub fn bessel_jy(n_max: usize, x: f64) -> (Vec<f64>, Vec<f64>) {
    assert!(x > 0.0 && x.is_finite(), "bessel_jy: x = {x} must be > 0");
    let m = miller_start(n_max.max(1), x);
    let f = miller_backward(m, x, -1.0);
    let mut norm = 0.0;
    for k in (2..=m).rev().step_by(2) {
        norm += 2.0 * f[k];
    }
    norm += f[0];
    let j: Vec<f64> = f.iter().map(|v| v / norm).collect();
    let (mut s0, mut s1) = (0.0, 0.0);
    for k in (1..=m / 2).rev() {
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        let kf = k as f64;
        s0 += sign * j[2 * k] / kf;
        if 2 * k < m {
            s1 += sign * (2.0 * kf + 1.0) / (4.0 * kf * (kf + 1.0)) * j[2 * k + 1];
        }
    }
    let el = (0.5 * x).ln() + EULER_GAMMA;
    let y0 = 2.0 / PI * (el * j[0] - 2.0 * s0);
    let y1 = 2.0 / PI * ((el - 1.0) * j[1] - j[0] / x - 4.0 * s1);
    let mut y = vec![y0, y1];
    for k in 1..n_max {
        y.push(2.0 * k as f64 / x * y[k] - y[k - 1]);
    }
    y.truncate(n_max + 1);
    (j[..=n_max].to_vec(), y)
}

/// `(eˣ K₀(x), eˣ K₁(x))`, `x > 0`, from
/// `K_ν(x) = ∫₀^∞ e^{−x cosh t} cosh νt dt` (A&S 9.6.24) by the trapezoidal rule, which
/// converges geometrically for this analytic, doubly-exponentially decaying integrand
/// (error ~ e^{−π²/h}, and ~ e^{−2π²/(x h²)} for the Gaussian-like peak at large x).
fn bessel_k01_scaled(x: f64) -> (f64, f64) {
    let h = 0.1f64.min(0.5 / x.sqrt());
    let (mut s0, mut s1) = (0.5, 0.5);
    let mut i = 1;
    loop {
        let t = i as f64 * h;
        // x (cosh t − 1) = 2x sinh²(t/2), without cancellation.
        let e = 2.0 * x * (0.5 * t).sinh().powi(2);
        let g = (-e).exp();
        s0 += g;
        s1 += g * t.cosh();
        if e - t > 60.0 {
            break;
        }
        i += 1;
    }
    (h * s0, h * s1)
}

/// `e^{−x} I_k(x)` and `eˣ K_k(x)` for `k = 0 … n_max`, `x > 0` (exponentially scaled, so
/// usable for any x).
///
/// `I_k`: Miller's backward recurrence `I_{k−1} = (2k/x) I_k + I_{k+1}` normalised by
/// `eˣ = I₀ + 2 Σ_{k≥1} I_k` (generating function `e^{(x/2)(t+1/t)} = Σ t^k I_k(x)` at t = 1). `K₀`, `K₁`: integral
/// representation (see `bessel_k01_scaled`), then the stable forward recurrence
/// `K_{k+1} = K_{k−1} + (2k/x) K_k`. Accuracy about 1e-14 relative.
pub fn bessel_ik_scaled(n_max: usize, x: f64) -> (Vec<f64>, Vec<f64>) {
    assert!(x > 0.0 && x.is_finite(), "bessel_ik: x = {x} must be > 0");
    let m = miller_start(n_max.max(1), x);
    let f = miller_backward(m, x, 1.0);
    let mut norm = 0.0;
    for v in f[1..].iter().rev() {
        norm += 2.0 * v;
    }
    norm += f[0];
    let i: Vec<f64> = f[..=n_max].iter().map(|v| v / norm).collect();
    let (k0, k1) = bessel_k01_scaled(x);
    let mut k = vec![k0, k1];
    for n in 1..n_max {
        k.push(k[n - 1] + 2.0 * n as f64 / x * k[n]);
    }
    k.truncate(n_max + 1);
    (i, k)
}

/// `I_k(x)` and `K_k(x)` for `k = 0 … n_max`, `0 < x < ~700` (see [`bessel_ik_scaled`]).
pub fn bessel_ik(n_max: usize, x: f64) -> (Vec<f64>, Vec<f64>) {
    let (i, k) = bessel_ik_scaled(n_max, x);
    let (up, down) = (x.exp(), (-x).exp());
    (
        i.into_iter().map(|v| v * up).collect(),
        k.into_iter().map(|v| v * down).collect(),
    )
}

/// `J_n(x)`, `x > 0`.
pub fn bessel_j(n: usize, x: f64) -> f64 {
    bessel_jy(n, x).0[n]
}

/// `Y_n(x)`, `x > 0`.
pub fn bessel_y(n: usize, x: f64) -> f64 {
    bessel_jy(n, x).1[n]
}

/// `I_n(x)`, `0 < x < ~700`.
pub fn bessel_i(n: usize, x: f64) -> f64 {
    bessel_ik(n, x).0[n]
}

/// `K_n(x)`, `0 < x < ~700`.
pub fn bessel_k(n: usize, x: f64) -> f64 {
    bessel_ik(n, x).1[n]
}

/// Kind of cylinder function, for the derivative rules (A&S 9.1.27, 9.6.26).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BesselKind {
    /// `J` or `Y`: `Z'_n = (Z_{n−1} − Z_{n+1})/2`, `Z_{−1} = −Z₁`.
    Ordinary,
    /// `I`: `I'_n = (I_{n−1} + I_{n+1})/2`, `I_{−1} = I₁`.
    ModifiedI,
    /// `K`: `K'_n = −(K_{n−1} + K_{n+1})/2`, `K_{−1} = K₁`.
    ModifiedK,
}

/// `Z'_n(x)` from the values `z[k] = Z_k(x)`, `k = 0 … n+1` (any common scale factor).
pub fn bessel_derivative(kind: BesselKind, z: &[f64], n: usize) -> f64 {
    let below = if n > 0 {
        z[n - 1]
    } else if kind == BesselKind::Ordinary {
        -z[1]
    } else {
        z[1]
    };
    match kind {
        BesselKind::Ordinary => 0.5 * (below - z[n + 1]),
        BesselKind::ModifiedI => 0.5 * (below + z[n + 1]),
        BesselKind::ModifiedK => -0.5 * (below + z[n + 1]),
    }
}

// ---------------------------------------------------------------------------------------------
// Annular plate, clamped inside, free outside
// ---------------------------------------------------------------------------------------------

/// Kirchhoff radial moment `M_r / (−D k² cos nθ)` at `x = kr` for `W = Z_n(kr)`:
/// `Z'' + ν(Z'/x − n² Z/x²) = −(1−ν) Z'/x + (σ + (1−ν) n²/x²) Z`, using Bessel's equation
/// `Z'' = −Z'/x + (σ + n²/x²) Z` (σ = −1 for J, Y; +1 for I, K).
fn plate_moment(z: f64, dz: f64, x: f64, n: f64, nu: f64, sigma: f64) -> f64 {
    -(1.0 - nu) * dz / x + (sigma + (1.0 - nu) * n * n / (x * x)) * z
}

/// Kirchhoff effective shear `V_r / (−D k³ cos nθ)` at `x = kr` for `W = Z_n(kr)`:
/// `Z''' + Z''/x − (1 + (2−ν) n²) Z'/x² + (3−ν) n² Z/x³ = σ Z' − (1−ν) n² (Z' − Z/x)/x²`
/// (same reduction by Bessel's equation and its derivative).
fn plate_shear(z: f64, dz: f64, x: f64, n: f64, nu: f64, sigma: f64) -> f64 {
    sigma * dz - (1.0 - nu) * n * n * (dz - z / x) / (x * x)
}

/// Characteristic determinant of the clamped(r=b)-free(r=a) annular plate for the frequency
/// parameter `lambda = k a`, `beta = b/a`, `n` nodal diameters. Columns J, Y, I, K (each scaled
/// by a positive factor: exponential scaling of I, K, then its largest entry); rows
/// `W(b)`, `W'(b)`, `M_r(a)`, `V_r(a)`. Continuous in λ (no poles): its sign changes are
/// exactly the eigenvalues.
fn annular_clamped_free_determinant(lambda: f64, beta: f64, nu: f64, n: usize) -> f64 {
    let (xb, xa) = (lambda * beta, lambda);
    let nf = n as f64;
    let (jb, yb) = bessel_jy(n + 1, xb);
    let (ja, ya) = bessel_jy(n + 1, xa);
    let (ib, kb) = bessel_ik_scaled(n + 1, xb);
    let (ia, ka) = bessel_ik_scaled(n + 1, xa);
    // I column multiplied by e^{−xa}, K column by e^{xb}: both leave this factor.
    let decay = (xb - xa).exp();
    let column = |zb: &[f64], sb: f64, za: &[f64], sa: f64, kind: BesselKind| {
        let sigma = if kind == BesselKind::Ordinary {
            -1.0
        } else {
            1.0
        };
        let (z_b, dz_b) = (sb * zb[n], sb * bessel_derivative(kind, zb, n));
        let (z_a, dz_a) = (sa * za[n], sa * bessel_derivative(kind, za, n));
        let c = [
            z_b,
            dz_b,
            plate_moment(z_a, dz_a, xa, nf, nu, sigma),
            plate_shear(z_a, dz_a, xa, nf, nu, sigma),
        ];
        let scale = c.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        c.map(|v| v / scale)
    };
    let cols = [
        column(&jb, 1.0, &ja, 1.0, BesselKind::Ordinary),
        column(&yb, 1.0, &ya, 1.0, BesselKind::Ordinary),
        column(&ib, decay, &ia, 1.0, BesselKind::ModifiedI),
        column(&kb, 1.0, &ka, decay, BesselKind::ModifiedK),
    ];
    let mut m = [[0.0; 4]; 4];
    for (j, col) in cols.iter().enumerate() {
        for (i, v) in col.iter().enumerate() {
            m[i][j] = *v;
        }
    }
    determinant(m)
}

/// Frequency parameters `Ω = ω a² √(ρh/D)` (= (ka)²) of the first `count` modes with
/// `nodal_diameters` nodal diameters of a Kirchhoff annular plate clamped at `r = b` and free
/// at `r = a`, `radius_ratio = b/a ∈ (0, 1)`. See [`annular_plate_clamped_free`].
pub fn annular_plate_clamped_free_parameters(
    radius_ratio: f64,
    poisson: f64,
    nodal_diameters: usize,
    count: usize,
) -> Vec<f64> {
    assert!(
        radius_ratio > 0.0 && radius_ratio < 1.0,
        "radius ratio b/a = {radius_ratio} must be in (0, 1)"
    );
    let det = |lambda: f64| {
        annular_clamped_free_determinant(lambda, radius_ratio, poisson, nodal_diameters)
    };
    // Radial wave spacing in ka is about π/(1 − b/a): step ≤ 1/40 of it, ≤ 0.1, and
    // geometric (10 %) near λ = 0.
    let h = (0.025 * PI / (1.0 - radius_ratio)).min(0.1);
    let step = |lambda: f64| h.min(0.1 * lambda);
    scan_roots(det, 1e-3, step, count, 1e5)
        .into_iter()
        .map(|l| l * l)
        .collect()
}

/// Natural frequencies (Hz) of the modes with `nodal_diameters` = n nodal diameters
/// (`w = W(r) cos nθ`; each n ≥ 1 frequency is a double eigenvalue of the plate, sin and cos)
/// of a Kirchhoff (thin) annular plate clamped at the inner edge `r = b` and free at the outer
/// edge `r = a`; the first `count` of them (0, 1, 2, … nodal circles).
///
/// Theory (Leissa, *Vibration of Plates*, NASA SP-160, 1969, ch. 2, annular plates; Vogel &
/// Skinner, J. Appl. Mech. 32 (1965) 926–931): `D∇⁴w + ρh ẅ = 0`, `D = E h³/(12(1−ν²))`;
/// `W = A J_n(kr) + B Y_n(kr) + C I_n(kr) + D K_n(kr)` with `k⁴ = ρhω²/D`; boundary conditions
/// `W(b) = W'(b) = 0` and, at `r = a`,
/// `M_r ∝ W'' + ν(W'/r − n²W/r²) = 0`,
/// `V_r = Q_r + (1/r)∂M_rθ/∂θ ∝ W''' + W''/r − (1 + (2−ν)n²) W'/r² + (3−ν) n² W/r³ = 0`.
/// The roots `ka` of the 4×4 determinant are found by a scan and bisection, with the Bessel
/// functions of this module; `f = (ka)²/(2π a²) √(D/(ρh))`.
/// Shear deformation and rotary inertia are neglected (thin plate: error grows like (h/a)²·Ω).
#[allow(clippy::too_many_arguments)]
pub fn annular_plate_clamped_free(
    inner_radius: f64,
    outer_radius: f64,
    thickness: f64,
    young: f64,
    poisson: f64,
    density: f64,
    nodal_diameters: usize,
    count: usize,
) -> Vec<f64> {
    let rigidity = young * thickness.powi(3) / (12.0 * (1.0 - poisson * poisson));
    let c = (rigidity / (density * thickness)).sqrt() / (2.0 * PI * outer_radius * outer_radius);
    annular_plate_clamped_free_parameters(
        inner_radius / outer_radius,
        poisson,
        nodal_diameters,
        count,
    )
    .into_iter()
    .map(|omega| omega * c)
    .collect()
}
