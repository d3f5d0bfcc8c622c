//! Checks of the reference solutions against published values, limits and independent
//! computations (run by `tests/program/reference_solutions.rs`).

use crate::reference::*;
use std::f64::consts::PI;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn clamped_free_roots_match_known_values() {
    let r = clamped_free_beam_roots(8);
    let known = [1.8751040687, 4.6940911330, 7.8547574382, 10.9955407349];
    for (a, b) in r.iter().zip(known) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
    // cos x = −sech x ≈ −2e^{−x}: x ≈ x₀ + (−1)^{n+1} 2e^{−x₀}, x₀ = (2n−1)π/2.
    for (i, a) in r.iter().enumerate().skip(4) {
        let x0 = (2 * i + 1) as f64 * PI / 2.0;
        let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
        let asym = x0 + sign * 2.0 * (-x0).exp();
        assert!((a - asym).abs() < 1e-10, "{a} vs {asym}");
    }
    for x in r {
        assert!((1.0 + x.cos() * x.cosh()).abs() < 1e-14 * x.cosh());
    }
}

#[test]
fn bessel_known_values() {
    let cases = [
        (bessel_j(0, 1.0), 0.7651976865579666),
        (bessel_y(0, 1.0), 0.08825696421567696),
        (bessel_i(0, 1.0), 1.2660658777520082),
        (bessel_k(0, 1.0), 0.42102443824070834),
        (bessel_j(1, 2.5), 0.4970941024642741),
        (bessel_y(1, 10.0), 0.24901542420695388),
        (bessel_k(1, 5.0), 0.004044613445452164),
        (bessel_i(3, 7.0), 85.17548684284386),
    ];
    for (got, want) in cases {
        assert!(rel(got, want) < 1e-13, "{got} vs {want}");
    }
}

/// Values of J_n, Y_n, I_n, K_n computed with mpmath 1.3 (30 digits), rounded to 17.
#[rustfmt::skip]
const TABLE: [(usize, f64, f64, f64, f64, f64); 96] = [
    (0, 0.001, 0.9999997500000156, -4.471416611375923, 1.0000002500000156, 7.023688800562382),
    (0, 0.1, 0.99750156206604, -1.5342386513503667, 1.0025015629340956, 2.427069024702017),
    (0, 0.5, 0.9384698072408129, -0.44451873350670656, 1.0634833707413236, 0.9244190712276659),
    (0, 1.0, 0.7651976865579666, 0.08825696421567696, 1.2660658777520084, 0.42102443824070834),
    (0, 2.5, -0.048383776468198, 0.4980703596152319, 3.289839144050123, 0.06234755320036619),
    (0, 5.0, -0.1775967713143383, -0.30851762524903376, 27.239871823604446, 0.0036910983340425942),
    (0, 7.0, 0.3000792705195556, -0.025949743967209265, 168.5939085102897, 0.0004247957418692318),
    (0, 10.0, -0.24593576445134835, 0.055671167283599395, 2815.7166284662544, 1.778006231616765e-05),
    (0, 15.0, -0.014224472826780772, 0.20546429603891828, 339649.3732979139, 9.819536482396435e-08),
    (0, 25.0, 0.09626678327595811, -0.12724943226800614, 5774560606.4663105, 3.4641615622131143e-12),
    (0, 40.0, 0.00736689058423729, 0.12593641705826092, 1.48947747934199e+16, 8.392861100099567e-19),
    (0, 60.0, -0.09147180408906187, 0.0473589522094494, 5.894077055609801e+24, 1.4138978405591078e-27),
    (1, 0.001, 0.0004999999375000026, -636.6221672311394, 0.0005000000625000026, 999.9962381560856),
    (1, 0.1, 0.049937526036242, -6.4589510947020266, 0.050062526047092694, 9.853844780870606),
    (1, 0.5, 0.2422684576748739, -1.471472392670243, 0.2578943053908963, 1.656441120003301),
    (1, 1.0, 0.4400505857449335, -0.7812128213002887, 0.565159103992485, 0.6019072301972346),
    (1, 2.5, 0.49709410246427405, 0.1459181379667858, 2.5167162452886984, 0.07389081634774707),
    (1, 5.0, -0.32757913759146523, 0.14786314339122683, 24.335642142450528, 0.004044613445452165),
    (1, 7.0, -0.004682823482345833, -0.30266723702418485, 156.03909286995545, 0.00045418248688489695),
    (1, 10.0, 0.04347274616886144, 0.24901542420695388, 2670.9883037012546, 1.8648773453825585e-05),
    (1, 15.0, 0.20510403861352275, 0.02107362803687351, 328124.9219702064, 1.0141729369762092e-07),
    (1, 25.0, -0.1253502495802899, -0.09882996478323741, 5657865129.878701, 3.5327780731999337e-12),
    (1, 40.0, 0.126038318037585, -0.005793505821549633, 1.4707396163259352e+16, 8.497131954861039e-19),
    (1, 60.0, 0.046598383758166315, 0.09186960936986689, 5.844751588390468e+24, 1.4256320265171043e-27),
    (2, 0.001, 1.2499998958333365e-07, -1273239.8630456675, 1.25000010416667e-07, 1999999.5000009716),
    (2, 0.1, 0.0012489586587999188, -127.64478324269017, 0.001251041992241759, 199.50396464211414),
    (2, 0.5, 0.03060402345868264, -5.441370837174266, 0.031906149177738256, 7.5501835512408695),
    (2, 1.0, 0.11490348493190047, -1.6506826068162543, 0.13574766976703828, 1.6248388986351774),
    (2, 2.5, 0.44605905843961724, -0.38133584924180325, 1.2764661478191643, 0.12146020627856384),
    (2, 5.0, 0.046565116277752214, 0.36766288260552454, 17.505614966624236, 0.00530894371222346),
    (2, 7.0, -0.30141722008594013, -0.060526609468272125, 124.01131054744528, 0.0005545621666934881),
    (2, 10.0, 0.2546303136851206, -0.0058680824422086145, 2281.5189677260037, 2.150981700693277e-05),
    (2, 15.0, 0.04157167797525047, -0.20265447896733513, 295899.38370188634, 1.117176706503138e-07),
    (2, 25.0, -0.1062948032423813, 0.11934303508534715, 5321931396.0760145, 3.746783808069109e-12),
    (2, 40.0, -0.0010649746823580396, -0.1262260923493384, 1.4159404985256932e+16, 8.817717697842618e-19),
    (2, 60.0, 0.09302508354766742, -0.044296631897120506, 5.699252002663452e+24, 1.461418908109678e-27),
    (3, 0.001, 2.0833332031250032e-11, -5092958815.560503, 2.08333346354167e-11, 7999999000.000125),
    (3, 0.1, 2.0820315754756262e-05, -5099.332378612905, 2.084635742232715e-05, 7990.012430465436),
    (3, 0.5, 0.002563729994587244, -42.059494304723884, 0.002645111968990286, 62.05790952993026),
    (3, 1.0, 0.019563353982668407, -5.821517605964729, 0.022168424924331902, 7.101262824737945),
    (3, 2.5, 0.21660039103911352, -0.756055496753671, 0.4743704087780356, 0.2682271463934492),
    (3, 5.0, 0.364831230613667, 0.14626716269319276, 10.331150169151138, 0.008291768415230933),
    (3, 7.0, -0.16755558799533424, 0.26808060304231507, 85.17548684284387, 0.0007710751535668902),
    (3, 10.0, 0.058379379305186815, -0.2513626571838373, 1758.3807166108531, 2.725270025659869e-05),
    (3, 15.0, -0.19401825782012264, -0.07511482242816288, 249218.41964970337, 1.312086725377046e-07),
    (3, 25.0, 0.10834308106150889, 0.11792485039689295, 4806356106.506539, 4.132263482490991e-12),
    (3, 40.0, -0.1261448155058208, -0.006829103413384208, 1.329145566473366e+16, 9.3789037246453e-19),
    (3, 60.0, -0.04039671152165516, -0.09482271816300826, 5.464801454879571e+24, 1.5230599537244162e-27),
    (5, 0.001, 2.604166558159724e-19, -2.444620078680264e+17, 2.6041667751736133e-19, 3.83999976000001e+17),
    (5, 0.1, 2.603081790964441e-09, -24461484.502303917, 2.605251929893697e-09, 38376009.99583593),
    (5, 0.5, 8.053627241357474e-06, -7946.301478807473, 8.223171313109265e-06, 12097.979476096394),
    (5, 1.0, 0.00024975773021123444, -260.4058666258122, 0.0002714631559569719, 360.9605896012407),
    (5, 2.5, 0.01950162513450322, -3.8301760007407517, 0.03284347517202321, 2.716884290786543),
    (5, 5.0, 0.26114054612017007, -0.4536948224911019, 2.1579745473225467, 0.03270627371203186),
    (5, 7.0, 0.34789632475118326, 0.06370223524859028, 26.885486389773853, 0.0021601994128739527),
    (5, 10.0, -0.23406152818679363, 0.13540304768936232, 777.18828640326, 5.754184998531228e-05),
    (5, 15.0, 0.13045613456502955, 0.1671727157594002, 144572.01120063404, 2.1878261369258227e-07),
    (5, 25.0, -0.06600799539842299, -0.14705799311372267, 3472466208.7419167, 5.648592136528414e-12),
    (5, 40.0, 0.12257346597711778, 0.031869448780850365, 1.0858318337624282e+16, 1.1423814375953184e-18),
    (5, 60.0, 0.0274547442283441, 0.09946463284045089, 4.777765207256172e+24, 1.7382232741886986e-27),
    (8, 0.001, 9.688119770568098e-32, -4.1069616221749396e+29, 9.688120308796988e-32, 6.451199769600004e+29),
    (8, 0.1, 9.685429231594647e-16, -41084285530817.04, 9.69081152055655e-16, 64488964799200.125),
    (8, 0.5, 3.75822315479761e-10, -106081857.5158798, 3.8107848810317677e-10, 163683808.12448186),
    (8, 1.0, 9.4223441726045e-08, -425674.6184865067, 9.960624033363979e-08, 622552.1229586678),
    (8, 2.5, 0.0001240773664298689, -337.95968675654825, 0.0001755968950240752, 339.5354135074448),
    (8, 5.0, 0.018405216654802, -2.8208693825455953, 0.07411663215970846, 0.7143624205645256),
    (8, 7.0, 0.12797053402821254, -0.6114352469212657, 2.0109263061007323, 0.02336982304466329),
    (8, 10.0, 0.3178541268438572, 0.0010754737339629143, 116.06643267013685, 0.00033623939953126463),
    (8, 15.0, -0.17398365908895735, -0.14053398292691227, 39437.03528537204, 7.457619624506637e-07),
    (8, 25.0, 0.1530061666573989, 0.05879476686163041, 1581946317.4805567, 1.2042228190845195e-11),
    (8, 40.0, -0.08630831524531733, 0.09377044928139815, 6643061873342099.0, 1.8452295101416735e-18),
    (8, 60.0, -0.10330342693895792, -0.005822549381484311, 3.4449680648847793e+24, 2.397840889674899e-27),
    (13, 0.001, 1.9603324646060763e-53, -1.2490420056418852e+51, 1.9603325346179512e-53, 1.9619905127251974e+51),
    (13, 0.1, 1.959982469407178e-27, -1.2493022262718515e+25, 1.960682588160078e-27, 1.9615818520127697e+25),
    (13, 0.5, 2.3823232712155037e-18, -1.0285596069836542e+16, 2.403689257820005e-18, 1.5989152340581058e+16),
    (13, 1.0, 1.925616764480173e-14, -1275361870151.9836, 1.9956316782072008e-14, 1921576392792.9941),
    (13, 2.5, 2.61154471836379e-09, -9555344.31920706, 3.264687032292391e-09, 11567967.637542918),
    (13, 5.0, 1.5207582205849454e-05, -1745.5617222856354, 3.715680719595662e-05, 965.8503276608521),
    (13, 7.0, 0.0007702215725221331, -37.831750823146336, 0.004449031198069076, 7.608793528068567),
    (13, 10.0, 0.028972083926776766, -1.363454319803315, 1.0652327130742787, 0.028608114770176128),
    (13, 15.0, 0.2787148734373273, -0.04612981798649977, 1404.7247994728775, 1.7928358291881697e-05),
    (13, 25.0, 0.09828287584358864, 0.14185099359337447, 198298258.9702393, 8.948232790925467e-11),
    (13, 40.0, -0.06237837342418682, 0.113733943596204, 1787449207713414.8, 6.650998713612697e-18),
    (13, 60.0, -0.08393822925995784, 0.0618252389679518, 1.432433078591075e+24, 5.6858221167019064e-27),
    (21, 0.001, 9.333105488286723e-90, -1.6240696801345806e+87, 9.33310570040276e-90, 2.5510826242372955e+87),
    (21, 0.1, 9.332045071801791e-48, -1.6242726818976434e+45, 9.334166232168144e-48, 2.5507637917721396e+45),
    (21, 0.5, 4.43774561105017e-33, -3.416581964223591e+30, 4.46303184285523e-33, 5.333316785352948e+30),
    (21, 1.0, 9.22762198209667e-27, -1.6445047095479366e+24, 9.439742021144581e-27, 2.519402948201736e+24),
    (21, 2.5, 1.9763951096255497e-18, -7724384619810290.0, 2.2780523684066845e-18, 1.0378257625691298e+16),
    (21, 5.0, 3.343819986753189e-12, -4667608668.151212, 5.902353044065057e-12, 3923995650.516278),
    (21, 7.0, 2.9664715433750245e-09, -5420601.800945319, 9.037905411646709e-09, 2498995.019247049),
    (21, 10.0, 2.9071994666910343e-06, -5932.7708473753455, 2.8317864648553148e-05, 759.0211367774074),
    (21, 15.0, 0.0030537844503483744, -7.139103900827546, 0.5296793586470854, 0.036572638250405756),
    (21, 25.0, 0.16462380368494298, 0.13727398409180186, 1147810.3959338185, 1.3341029132847327e-08),
    (21, 40.0, 0.10514961053424556, -0.087380880730417, 63515117186626.56, 1.7424876333193145e-16),
    (21, 60.0, 0.009987320876403975, -0.10595346813600327, 1.5043562347576887e+23, 5.228538658640434e-26),
];

#[test]
fn bessel_against_mpmath_table() {
    for &(n, x, j, y, i, k) in TABLE.iter() {
        let (jj, yy) = bessel_jy(n, x);
        let (ii, kk) = bessel_ik(n, x);
        // J, Y: relative; in the oscillatory range x > n relative to the envelope
        // √(J²+Y²) instead (absolute accuracy near their zeros).
        let (sj, sy) = if x > n as f64 {
            (j.hypot(y), j.hypot(y))
        } else {
            (j.abs(), y.abs())
        };
        let errs = [
            (jj[n] - j).abs() / sj,
            (yy[n] - y).abs() / sy,
            rel(ii[n], i),
            rel(kk[n], k),
        ];
        assert!(errs.iter().all(|e| *e < 1e-13), "n={n} x={x}: {errs:?}");
    }
}

#[test]
fn bessel_wronskians() {
    for n in 0..=40 {
        for &x in &[
            1e-3, 0.05, 0.3, 1.0, 2.0, 3.7, 6.0, 9.5, 14.0, 22.0, 33.0, 47.0, 60.0,
        ] {
            let (j, y) = bessel_jy(n + 1, x);
            let (i, k) = bessel_ik_scaled(n + 1, x);
            let dj = bessel_derivative(BesselKind::Ordinary, &j, n);
            let dy = bessel_derivative(BesselKind::Ordinary, &y, n);
            let di = bessel_derivative(BesselKind::ModifiedI, &i, n);
            let dk = bessel_derivative(BesselKind::ModifiedK, &k, n);
            let w1 = (j[n] * dy - dj * y[n]) / (2.0 / (PI * x));
            // Scaled functions: the e^{±x} factors cancel in the products.
            let w2 = (i[n] * dk - di * k[n]) / (-1.0 / x);
            assert!((w1 - 1.0).abs() < 1e-12, "J/Y Wronskian n={n} x={x}: {w1}");
            assert!((w2 - 1.0).abs() < 1e-12, "I/K Wronskian n={n} x={x}: {w2}");
        }
    }
}

#[test]
fn euler_bernoulli_frequency_formula() {
    // Steel 1 m × 20 mm × 10 mm, bending about the 20 mm side: f₁ = 8.3553 Hz by hand.
    let (e, rho, b, h, l) = (210e9, 7850.0, 0.02, 0.01, 1.0);
    let f = cantilever_euler_bernoulli(l, e, rho, b * h, b * h.powi(3) / 12.0, 3);
    let c = (e * b * h.powi(3) / 12.0 / (rho * b * h)).sqrt() / (2.0 * PI * l * l);
    assert!(rel(f[0], 1.8751040687f64.powi(2) * c) < 1e-10);
    assert!(rel(f[0], 8.3553) < 1e-4, "{}", f[0]);
    assert!(rel(f[2] / f[0], (7.8547574382f64 / 1.8751040687).powi(2)) < 1e-9);
}

const STEEL: (f64, f64, f64) = (210e9, 0.3, 7850.0);

#[test]
fn cowper_coefficient() {
    assert!(rel(cowper_shear_coefficient_rectangle(0.0), 5.0 / 6.0) < 1e-15);
    assert!(rel(cowper_shear_coefficient_rectangle(0.3), 13.0 / 15.3) < 1e-15);
}

/// ∫₀¹ φ‴² / ∫₀¹ φ″² and ∫₀¹ φ′² / ∫₀¹ φ² for the clamped-free Euler–Bernoulli mode
/// φ(ξ) = cosh βξ − cos βξ − s (sinh βξ − sin βξ), by Simpson's rule.
fn eb_mode_integral_ratios(beta: f64) -> (f64, f64) {
    let s = (beta.cosh() + beta.cos()) / (beta.sinh() + beta.sin());
    // k-th derivative of φ divided by β^k.
    let d = |k: usize, x: f64| {
        let (ch, sh) = ((beta * x).cosh(), (beta * x).sinh());
        let (c, sn) = ((beta * x).cos(), (beta * x).sin());
        match k % 4 {
            0 => ch - c - s * (sh - sn),
            1 => sh + sn - s * (ch - c),
            2 => ch + c - s * (sh + sn),
            _ => sh - sn - s * (ch + c),
        }
    };
    let n = 4000;
    let mut sums = [0.0; 4];
    for i in 0..=n {
        let x = i as f64 / n as f64;
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        for (k, sum) in sums.iter_mut().enumerate() {
            *sum += w * d(k, x).powi(2);
        }
    }
    (
        beta * beta * sums[3] / sums[2],
        beta * beta * sums[1] / sums[0],
    )
}

#[test]
fn timoshenko_tends_to_euler_bernoulli_with_first_order_correction() {
    // ω_T/ω_EB = 1 − ½ (r/L)² [(E/kG) ∫φ‴²/∫φ″² + ∫φ′²/∫φ²] + O((r/L)⁴), r² = I/A:
    // Rayleigh quotient of the Timoshenko beam evaluated with the Euler–Bernoulli mode
    // (shear compliance and rotary inertia as first-order perturbations).
    let (e, nu, rho) = STEEL;
    let e_over_kg = 2.0 * (1.0 + nu) / cowper_shear_coefficient_rectangle(nu);
    let (l, w) = (1.0, 0.03);
    let betas = clamped_free_beam_roots(4);
    for h in [0.004, 0.002, 0.001] {
        let t = cantilever_timoshenko(l, e, nu, rho, w, h, 4, BendingAxis::Width);
        let eb = cantilever_euler_bernoulli(l, e, rho, w * h, w * h.powi(3) / 12.0, 4);
        let r2 = h * h / 12.0 / (l * l);
        for (i, beta) in betas.iter().enumerate() {
            let (a, b) = eb_mode_integral_ratios(*beta);
            let predicted = 0.5 * r2 * (e_over_kg * a + b);
            let defect = 1.0 - t[i] / eb[i];
            // The relative mismatch of the correction is itself O((r/L)² β²).
            let tol = 10.0 * r2 * beta * beta + 1e-6;
            assert!(
                rel(defect, predicted) < tol,
                "h={h} mode {}: 1 − ratio = {defect:e}, first-order {predicted:e}",
                i + 1
            );
        }
    }
    // And the trivial limit.
    let t = cantilever_timoshenko(1.0, e, nu, rho, 0.01, 1e-5, 4, BendingAxis::Width);
    let eb = cantilever_euler_bernoulli(1.0, e, rho, 1e-7, 1e-2 * 1e-15 / 12.0, 4);
    for (a, b) in t.iter().zip(&eb) {
        assert!(rel(*a, *b) < 1e-8, "{a} vs {b}");
    }
}

#[test]
fn timoshenko_infinite_shear_stiffness_no_rotary_inertia_is_euler_bernoulli() {
    let (ei, rho_a) = (2.0e4, 3.0);
    let t = timoshenko_clamped_free_omegas(2.0, ei, 1e12 * ei, rho_a, 1e-12 * rho_a, 6);
    for (w, b) in t.iter().zip(clamped_free_beam_roots(6)) {
        let exact = b * b / 4.0 * (ei / rho_a).sqrt();
        assert!(rel(*w, exact) < 1e-9, "{w} vs {exact}");
    }
}

/// Clamped-free Timoshenko characteristic function by shooting: RK4 on
/// (w, w′, ψ, ψ′)′ = (w′, ψ′ − q w, ψ′, (−kGA (w′ − ψ) − ρIω² ψ)/EI) from the two clamped
/// starts (w′(0), ψ′(0)) = (1, 0), (0, 1); 2×2 determinant of (ψ′(L), w′(L) − ψ(L)).
fn timoshenko_shooting(omega: f64, l: f64, ei: f64, kga: f64, rho_a: f64, rho_i: f64) -> f64 {
    let q = rho_a * omega * omega / kga;
    let rhs = |y: [f64; 4]| {
        [
            y[1],
            y[3] - q * y[0],
            y[3],
            (-kga * (y[1] - y[2]) - rho_i * omega * omega * y[2]) / ei,
        ]
    };
    let steps = 3000;
    let dx = l / steps as f64;
    let mut ends = [[0.0; 2]; 2];
    let starts = [[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]];
    for (start, end) in starts.iter().zip(&mut ends) {
        let mut y = *start;
        for _ in 0..steps {
            let k1 = rhs(y);
            let k2 = rhs(std::array::from_fn(|i| y[i] + 0.5 * dx * k1[i]));
            let k3 = rhs(std::array::from_fn(|i| y[i] + 0.5 * dx * k2[i]));
            let k4 = rhs(std::array::from_fn(|i| y[i] + dx * k3[i]));
            y = std::array::from_fn(|i| {
                y[i] + dx / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            });
        }
        *end = [y[3], y[1] - y[2]];
    }
    ends[0][0] * ends[1][1] - ends[0][1] * ends[1][0]
}

#[test]
fn timoshenko_thick_beam_against_shooting_including_second_spectrum() {
    // h/L = 0.3: modes 6–8 lie above the critical frequency √(kGA/ρI).
    let (e, nu, rho) = STEEL;
    let (l, w, h): (f64, f64, f64) = (1.0, 0.05, 0.3);
    let (area, inertia) = (w * h, w * h.powi(3) / 12.0);
    let kga = cowper_shear_coefficient_rectangle(nu) * e / (2.0 * (1.0 + nu)) * area;
    let (ei, rho_a, rho_i) = (e * inertia, rho * area, rho * inertia);
    let f = cantilever_timoshenko(l, e, nu, rho, w, h, 8, BendingAxis::Width);
    let critical = (kga / rho_i).sqrt();
    assert!(2.0 * PI * f[7] > critical && 2.0 * PI * f[0] < critical);
    let shoot = |om: f64| timoshenko_shooting(om, l, ei, kga, rho_a, rho_i);
    for fi in &f {
        let om = 2.0 * PI * fi;
        let (lo, hi) = (shoot(om * (1.0 - 1e-7)), shoot(om * (1.0 + 1e-7)));
        assert!(lo * hi < 0.0, "no shooting root at {fi} Hz");
    }
    // No root missed: the shooting function changes sign exactly 8 times below f₈(1+1e-7).
    let mut changes = 0;
    let top = 2.0 * PI * f[7] * (1.0 + 1e-7);
    let mut prev = shoot(1.0);
    for i in 1..=800 {
        let v = shoot(top * i as f64 / 800.0);
        if (v < 0.0) != (prev < 0.0) {
            changes += 1;
        }
        prev = v;
    }
    assert_eq!(changes, 8);
    // Bending about the other axis swaps width and height.
    let g = cantilever_timoshenko(l, e, nu, rho, h, w, 8, BendingAxis::Height);
    for (a, b) in f.iter().zip(&g) {
        assert!(rel(*a, *b) < 1e-12);
    }
}

#[test]
fn torsion_constant_of_rectangles() {
    // J/(a b³) from the same series by mpmath (30 digits) ...
    let exact = [
        (1.0, 0.140577014955154),
        (2.0, 0.228681677119571),
        (10.0, 0.312325037457205),
    ];
    for (ratio, beta) in exact {
        let j = saint_venant_torsion_constant_rectangle(ratio, 1.0);
        assert!(rel(j / ratio, beta) < 1e-13, "{ratio}: {}", j / ratio);
    }
    // ... and the classical 3-digit table of k₁ = J/(a b³) (Timoshenko & Goodier, Theory of
    // Elasticity, §109; also in Roark's Formulas for Stress and Strain).
    let roark = [
        (1.0, 0.141),
        (1.5, 0.196),
        (2.0, 0.229),
        (3.0, 0.263),
        (4.0, 0.281),
        (5.0, 0.291),
        (10.0, 0.312),
    ];
    for (ratio, beta) in roark {
        let j = saint_venant_torsion_constant_rectangle(1.0, ratio);
        assert!((j / ratio - beta).abs() < 6e-4, "{ratio}: {}", j / ratio);
    }
    // Thin strip: J → a b³/3 (1 − 0.630249 b/a) (the sum → Σ n⁻⁵ = (31/32) ζ(5)).
    let thin = saint_venant_torsion_constant_rectangle(1000.0, 1.0) / 1000.0;
    assert!(
        (thin - (1.0 - 0.630249 / 1000.0) / 3.0).abs() < 1e-9,
        "{thin}"
    );
}

#[test]
fn torsion_frequencies() {
    let (g, rho, l) = (80e9, 7850.0, 0.5);
    let f = cantilever_torsion_saint_venant(l, g, rho, 0.02, 0.02, 3);
    // Square a×a: J = 0.140577 a⁴, I_p = a⁴/6.
    let f1 = 1.0 / (4.0 * l) * (g * 0.140577014955154 * 6.0 / rho).sqrt();
    assert!(rel(f[0], f1) < 1e-12, "{} vs {f1}", f[0]);
    assert!(rel(f[1], 3.0 * f1) < 1e-12 && rel(f[2], 5.0 * f1) < 1e-12);
    let a = cantilever_torsion_saint_venant(l, g, rho, 0.04, 0.01, 1);
    let b = cantilever_torsion_saint_venant(l, g, rho, 0.01, 0.04, 1);
    assert!(rel(a[0], b[0]) < 1e-15);
}

/// Ω = ω a² √(ρh/D), ν = 0.3: the same frequency equation solved independently with
/// mpmath 1.3 (its own Bessel functions, derivatives from DLMF 10.6.7/10.29.5 and the
/// unsimplified M_r, V_r expressions, 20 digits), rounded to 16 digits. A coarse mpmath
/// scan confirmed no root is missed for b/a = 0.1, 0.5 (all n) and 0.9 (n = 0, 5).
#[rustfmt::skip]
const ANNULAR_MPMATH: [(f64, usize, [f64; 3]); 25] = [
    (0.1, 0, [4.237379772481656, 25.26182882103003, 73.90064278139828]),
    (0.1, 1, [3.478138426173525, 27.67280548501788, 77.48677666797656]),
    (0.1, 2, [5.622703256443549, 36.94089478234452, 90.18349490071616]),
    (0.1, 3, [12.45052070381869, 53.20260045111923, 113.036892720341]),
    (0.1, 5, [33.49494409399399, 96.75613253897674, 175.7449051122107]),
    (0.3, 0, [6.660367308755531, 42.61421204715106, 123.4661129484218]),
    (0.3, 1, [6.552314242939725, 44.63114649575712, 125.8234083912148]),
    (0.3, 2, [7.956486544458516, 50.94727184765654, 133.0848147516847]),
    (0.3, 3, [13.27573299804432, 62.0527894354314, 145.6913721891018]),
    (0.3, 5, [33.55739667598565, 98.7833453199149, 188.4055831615253]),
    (0.5, 0, [13.02425666215785, 85.03282540485078, 243.6940374317262]),
    (0.5, 1, [13.28978141020494, 86.70583132126508, 245.4358164716016]),
    (0.5, 2, [14.70381247115273, 91.73815470172384, 250.6824867322212]),
    (0.5, 3, [18.56198878581626, 100.167455488159, 259.4915267949697]),
    (0.5, 5, [35.73009154948632, 127.4466886393861, 288.1138995701955]),
    (0.7, 0, [36.95263800267993, 239.8420113965349, 680.6513618858276]),
    (0.7, 1, [37.49833719653451, 241.2807089132296, 682.048546263939]),
    (0.7, 2, [39.27686551405395, 245.5867969404862, 686.2409092326745]),
    (0.7, 3, [42.65446085294531, 252.7321959157249, 693.2306564051821]),
    (0.7, 5, [55.88037469964113, 275.3722729491102, 715.6142715179443]),
    (0.9, 0, [344.402283380704, 2188.820838797086, 6155.583022472873]),
    (0.9, 1, [345.16648270389, 2190.095647880989, 6156.763496405538]),
    (0.9, 2, [347.4657578980028, 2193.918419373373, 6160.30476959311]),
    (0.9, 3, [351.3197562118432, 2200.284213608794, 6166.206395544899]),
    (0.9, 5, [363.8280213967586, 2220.609238164661, 6185.087417593061]),
];

#[test]
fn annular_plate_against_independent_mpmath_solution() {
    for (beta, n, want) in ANNULAR_MPMATH {
        let got = annular_plate_clamped_free_parameters(beta, 0.3, n, 3);
        for (g, w) in got.iter().zip(want) {
            assert!(rel(*g, w) < 1e-11, "b/a={beta} n={n}: {g} vs {w}");
        }
    }
}

#[test]
fn annular_plate_against_blevins_table() {
    // Blevins, Formulas for Natural Frequency and Mode Shape (1979), annular plate clamped
    // inside, free outside, b/a = 0.5, ν = 0.3, fundamental λ² for n = 0…3 (3 digits;
    // the 18.5 is 18.56 cut off), as quoted in seamplex/feenox tests/annulus-modal.fee.
    for (n, table) in [(0, 13.0), (1, 13.3), (2, 14.7), (3, 18.5)] {
        let got = annular_plate_clamped_free_parameters(0.5, 0.3, n, 1)[0];
        assert!((got - table).abs() < 0.07, "n={n}: {got} vs {table}");
    }
}

#[test]
fn annular_plate_in_hertz() {
    // Steel disc a = 0.15 m, b = 0.075 m, h = 0.01 m: f = Ω/(2π a²) √(D/(ρh)).
    let (e, nu, rho) = STEEL;
    let f = annular_plate_clamped_free(0.075, 0.15, 0.01, e, nu, rho, 2, 2);
    let d = e * 1e-6 / (12.0 * (1.0 - nu * nu));
    let c = (d / (rho * 0.01)).sqrt() / (2.0 * PI * 0.15 * 0.15);
    assert!(rel(f[0], 14.70381247115273 * c) < 1e-12);
    assert!(rel(f[1], 91.73815470172385 * c) < 1e-12);
}

#[test]
fn narrow_annulus_tends_to_cantilever_strip() {
    // Width c = a − b ≪ a: a plate strip in cylindrical bending, Ω (1 − b/a)² → 1.8751².
    let strip = 1.8751040687f64.powi(2);
    let mut defects = Vec::new();
    for gap in [0.04, 0.02, 0.01] {
        for n in [0, 2] {
            let omega = annular_plate_clamped_free_parameters(1.0 - gap, 0.3, n, 2);
            let ratio = omega[0] * gap * gap / strip;
            assert!((ratio - 1.0).abs() < 2.0 * gap, "gap {gap} n={n}: {ratio}");
            let second = omega[1] * gap * gap / 4.6940911330f64.powi(2);
            assert!(
                (second - 1.0).abs() < 2.0 * gap,
                "gap {gap} n={n}: {second}"
            );
            if n == 0 {
                defects.push(ratio - 1.0);
            }
        }
    }
    // First order in the gap: halving it halves the defect.
    assert!((defects[0] / defects[1] - 2.0).abs() < 0.05, "{defects:?}");
    assert!((defects[1] / defects[2] - 2.0).abs() < 0.05, "{defects:?}");
    // Richardson extrapolation removes the O(gap) term.
    assert!((2.0 * defects[2] - defects[1]).abs() < 1e-4, "{defects:?}");
}

#[test]
fn small_hole_tends_to_free_plate_and_centre_supported_plate() {
    // n ≥ 2: the vanishing clamped hole no longer constrains; the free circular plate
    // (ν = 0.3: 5.358, 12.439 as commonly tabulated, e.g. Blevins 1979, ch. 11; here to
    // more digits from an mpmath solution of the free-plate 2×2 determinant). n = 0: plate point-supported at the centre (W = A(J₀ − I₀) +
    // B(Y₀ + 2K₀/π), free edge; mpmath: 3.751968, 20.90810). n = 1: the tilt mode → 0.
    let cases = [
        (2usize, [5.3583297879, 35.2601083154]),
        (3, [12.4389881654, 53.0077914492]),
    ];
    for (n, want) in cases {
        let got = annular_plate_clamped_free_parameters(1e-4, 0.3, n, 2);
        for (g, w) in got.iter().zip(want) {
            assert!(rel(*g, w) < 1e-6, "n={n}: {g} vs {w}");
        }
    }
    let point = [3.75196802078, 20.9081006725];
    let mut last = f64::INFINITY;
    for beta in [1e-2, 1e-3, 1e-4, 1e-6] {
        let got = annular_plate_clamped_free_parameters(beta, 0.3, 0, 2);
        let err = rel(got[0], point[0]).max(rel(got[1], point[1]));
        assert!(err < last, "b/a={beta}: {got:?}");
        last = err;
    }
    assert!(last < 1e-6, "{last}");
    let tilt: Vec<f64> = [1e-2, 1e-4, 1e-8]
        .iter()
        .map(|&b| annular_plate_clamped_free_parameters(b, 0.3, 1, 1)[0])
        .collect();
    assert!(tilt[0] > tilt[1] && tilt[1] > tilt[2], "{tilt:?}");
}
