//! Where the pressure difference between a reduced-interface model and the full model comes
//! from (issue 10, item b): reads a full and a reduced sweep folder of the built-in brake and
//! prints, per pad, the L2 differences of several reconstructions of the reduced model's
//! pressure, the same reconstructions applied to the full model's own forces (the floor a
//! perfect reduced model reaches) and to a uniform pressure (the patch test), and the full
//! model's corner against mid-side nodal pressures.
//!
//!     cargo run --release --example pressure_metrics -- PRESET FULL_DIR REDUCED_DIR MU N [aw]
//!
//! e.g. `small /work/runs/small-full /work/runs/small-106 0.5 106`. No MPI: the reduced
//! interface is rebuilt here (pure geometry) for its couplings and tributary areas.

use squeal::contact::tributary_areas;
use squeal::model::Model;
use squeal::reduce::{reduce_interface, GridSize, InterfaceSettings};
use squeal::results::{ContactMap, SurfacePressure};
use squeal::study::compare::patch_pressure_l2;
use squeal::study::config::Study;
use std::collections::BTreeMap;

fn read(dir: &str, mu: f64) -> ContactMap {
    let file = format!("{dir}/mu_{mu:.3}/contact.json");
    serde_json::from_slice(&std::fs::read(&file).expect(&file)).expect("contact.json")
}

/// sqrt(sum A (p - q)^2 / sum A q^2) over the nodes of `q`.
fn l2(p: &BTreeMap<usize, f64>, q: &BTreeMap<usize, f64>, area: &BTreeMap<usize, f64>) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (n, &qn) in q {
        let a = area[n];
        num += a * (p.get(n).copied().unwrap_or(0.0) - qn).powi(2);
        den += a * qn * qn;
    }
    (num / den).sqrt()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (preset, full_dir, red_dir) = (&args[1], &args[2], &args[3]);
    let mu: f64 = args[4].parse().unwrap();
    let count: usize = args[5].parse().unwrap();
    let area_weighting = args.get(6).is_some_and(|a| a == "aw");
    let study = Study::builtin(preset);
    let model = Model::from_spec(&study.model_spec()).unwrap();
    let settings = InterfaceSettings {
        area_weighting,
        ..InterfaceSettings::paper(GridSize::Count(count))
    };
    let reduced = reduce_interface(&model, &settings).unwrap();
    let (full, red) = (read(full_dir, mu), read(red_dir, mu));
    let mesh = &model.mesh;
    for pad in &reduced.pads {
        let surface = &mesh.surfaces[&pad.grid.surface];
        let area: BTreeMap<usize, f64> = tributary_areas(mesh, surface).into_iter().collect();
        let nodal = |m: &ContactMap| -> BTreeMap<usize, f64> {
            m.surface
                .iter()
                .filter(|s| s.pair == pad.pair)
                .map(|s| (s.node, s.pressure))
                .collect()
        };
        let p_full = nodal(&full);
        let p_red = nodal(&red);
        let forces: Vec<f64> = red
            .points
            .iter()
            .filter(|p| p.pair == pad.pair)
            .map(|p| p.normal_force)
            .collect();
        assert_eq!(forces.len(), pad.grid.count());
        let a_k: Vec<f64> = pad.grid.nodes.iter().map(|n| n.area).collect();
        // Patches: each surface node to the nearest reduced contact node.
        let patch: BTreeMap<usize, usize> = area
            .keys()
            .map(|&i| {
                let x = mesh.nodes[i];
                let d = |k: usize| {
                    let y = pad.grid.nodes[k].position;
                    (0..3).map(|c| (x[c] - y[c]).powi(2)).sum::<f64>()
                };
                let k = (0..pad.grid.count())
                    .min_by(|&a, &b| d(a).total_cmp(&d(b)))
                    .unwrap();
                (i, k)
            })
            .collect();
        // Reconstructions of a nodal pressure from reduced-node forces F_k.
        let m0 = |f: &[f64]| -> BTreeMap<usize, f64> {
            let mut out: BTreeMap<usize, f64> = area.keys().map(|&n| (n, 0.0)).collect();
            for (c, fk) in pad.couplings.iter().zip(f) {
                for n in &c.nodes {
                    *out.get_mut(&n.node).unwrap() += n.weight * fk / area[&n.node];
                }
            }
            out
        };
        let m1 = |f: &[f64]| -> BTreeMap<usize, f64> {
            let mut out: BTreeMap<usize, f64> = area.keys().map(|&n| (n, 0.0)).collect();
            for (c, fk) in pad.couplings.iter().zip(f) {
                let s: f64 = c.nodes.iter().map(|n| n.weight * area[&n.node]).sum();
                for n in &c.nodes {
                    *out.get_mut(&n.node).unwrap() += n.weight * fk / s;
                }
            }
            out
        };
        let m2 = |f: &[f64]| -> BTreeMap<usize, f64> {
            let mut num: BTreeMap<usize, f64> = area.keys().map(|&n| (n, 0.0)).collect();
            let mut den = num.clone();
            for (k, c) in pad.couplings.iter().enumerate() {
                for n in &c.nodes {
                    *num.get_mut(&n.node).unwrap() += n.weight * f[k];
                    *den.get_mut(&n.node).unwrap() += n.weight * a_k[k];
                }
            }
            num.iter()
                .map(|(&n, &v)| {
                    let d = den[&n];
                    (
                        n,
                        if d > 0.0 {
                            v / d
                        } else {
                            f[patch[&n]] / a_k[patch[&n]]
                        },
                    )
                })
                .collect()
        };
        // Patch restriction of a nodal pressure: force over each patch / its nodes' area.
        let restrict = |p: &BTreeMap<usize, f64>| -> (Vec<f64>, Vec<f64>) {
            let (mut f, mut a) = (vec![0.0; pad.grid.count()], vec![0.0; pad.grid.count()]);
            for (&i, &k) in &patch {
                f[k] += p[&i] * area[&i];
                a[k] += area[&i];
            }
            (f, a)
        };
        let patch_l2 = |p: &BTreeMap<usize, f64>, q: &BTreeMap<usize, f64>| {
            let (fp, a) = restrict(p);
            let (fq, _) = restrict(q);
            let (mut num, mut den) = (0.0, 0.0);
            for k in 0..fp.len() {
                if a[k] > 0.0 {
                    num += (fp[k] - fq[k]).powi(2) / a[k];
                    den += fq[k].powi(2) / a[k];
                }
            }
            (num / den).sqrt()
        };
        // Reduced-node pressures F_k / A_k against the full force over the patch.
        let (f_patch, a_patch) = restrict(&p_full);
        let (mut num, mut den) = (0.0, 0.0);
        for k in 0..forces.len() {
            if a_patch[k] > 0.0 {
                let pf = f_patch[k] / a_patch[k];
                num += a_k[k] * (forces[k] / a_k[k] - pf).powi(2);
                den += a_k[k] * pf * pf;
            }
        }
        let node_l2 = (num / den).sqrt();
        println!(
            "pad {} (N = {}, area weighting {area_weighting}), mu {mu}:",
            pad.pair, count
        );
        println!(
            "  surface nodes {}, per reduced node {:.2}",
            area.len(),
            area.len() as f64 / count as f64
        );
        println!(
            "  as written (M0 spread / lumped area) vs full: {:.1} % (recomputed here {:.1} %)",
            100.0 * l2(&p_red, &p_full, &area),
            100.0 * l2(&m0(&forces), &p_full, &area)
        );
        println!(
            "  M1 (w A spread)      vs full: {:.1} %",
            100.0 * l2(&m1(&forces), &p_full, &area)
        );
        println!(
            "  M2 (interp. F_k/A_k) vs full: {:.1} %",
            100.0 * l2(&m2(&forces), &p_full, &area)
        );
        println!(
            "  patch restriction of the written fields: {:.1} %; F_k/A_k vs full patch force/area: {:.1} %",
            100.0 * patch_l2(&p_red, &p_full),
            100.0 * node_l2
        );
        // compare's metric (patches of the reduced contact points) on the field the sweep
        // now writes (M2) and on the old spread (M0).
        let surface_of = |p: &BTreeMap<usize, f64>| -> Vec<SurfacePressure> {
            p.iter()
                .map(|(&node, &pressure)| SurfacePressure {
                    pair: pad.pair.clone(),
                    node,
                    position: mesh.nodes[node],
                    area: area[&node],
                    pressure,
                })
                .collect()
        };
        let points: Vec<[f64; 3]> = pad.grid.nodes.iter().map(|n| n.position).collect();
        let full_surface = surface_of(&p_full);
        println!(
            "  compare's patch L2: M2 field {:.1} %, M0 field {:.1} %; uniform-pressure patch test on M2 {:.1e}",
            100.0 * patch_pressure_l2(&full_surface, &surface_of(&m2(&forces)), &points).unwrap(),
            100.0 * patch_pressure_l2(&full_surface, &surface_of(&m0(&forces)), &points).unwrap(),
            {
                let u: BTreeMap<usize, f64> = area.keys().map(|&n| (n, 1e6)).collect();
                let fu: Vec<f64> = a_k.iter().map(|a| 1e6 * a).collect();
                patch_pressure_l2(&surface_of(&u), &surface_of(&m2(&fu)), &points).unwrap()
            }
        );
        // Floors: the full model's own patch forces through each reconstruction.
        let floor: Vec<f64> = f_patch.clone();
        println!(
            "  floor (full's patch forces as F_k): M0 {:.1} %, M1 {:.1} %, M2 {:.1} %",
            100.0 * l2(&m0(&floor), &p_full, &area),
            100.0 * l2(&m1(&floor), &p_full, &area),
            100.0 * l2(&m2(&floor), &p_full, &area)
        );
        // Patch test: a uniform pressure.
        let p0 = 1e6;
        let uniform: BTreeMap<usize, f64> = area.keys().map(|&n| (n, p0)).collect();
        let fu: Vec<f64> = a_k.iter().map(|a| p0 * a).collect();
        println!(
            "  patch test (uniform p): M0 {:.2} %, M1 {:.2} %, M2 {:.2e} %, patch-restricted M0 {:.2} %",
            100.0 * l2(&m0(&fu), &uniform, &area),
            100.0 * l2(&m1(&fu), &uniform, &area),
            100.0 * l2(&m2(&fu), &uniform, &area),
            100.0 * patch_l2(&m0(&fu), &uniform)
        );
        // The full model's own nodal pressure: corners against mid-side nodes, in contact.
        let mut corner = std::collections::BTreeSet::new();
        for f in &surface.faces {
            corner.extend(f.nodes[..3].iter().copied());
        }
        let mean = |pick: bool| {
            let v: Vec<f64> = p_full
                .iter()
                .filter(|(n, p)| corner.contains(n) == pick && **p > 0.0)
                .map(|(_, p)| *p)
                .collect();
            (v.iter().sum::<f64>() / v.len() as f64, v.len())
        };
        let ((pc, nc), (pm, nm)) = (mean(true), mean(false));
        let (ac, am) = (
            area.iter()
                .filter(|(n, _)| corner.contains(n))
                .map(|(_, a)| *a)
                .collect::<Vec<_>>(),
            area.iter()
                .filter(|(n, _)| !corner.contains(n))
                .map(|(_, a)| *a)
                .collect::<Vec<_>>(),
        );
        let stats = |v: &[f64]| {
            let m = v.iter().sum::<f64>() / v.len() as f64;
            (
                v.iter().copied().fold(f64::MAX, f64::min) / m,
                v.iter().copied().fold(0.0, f64::max) / m,
                m,
            )
        };
        let (sc, sm) = (stats(&ac), stats(&am));
        println!(
            "  full: mean pressure at loaded corners {pc:.4e} ({nc}), mid-sides {pm:.4e} ({nm}); lumped areas corners {:.2}-{:.2} x {:.3e}, mid-sides {:.2}-{:.2} x {:.3e}",
            sc.0, sc.1, sc.2, sm.0, sm.1, sm.2
        );
    }
}
