//! Single against multi-right-hand-side solves with one MUMPS LU of K - sigma M of a preset:
//! what a block Krylov method for the CEA would gain. Run it with
//!
//!     mpirun -n 2 target/release/examples/block_solve_bench [PRESET] [BLOCK] [ROUNDS]

use squeal::fem::element::MassRule;
use squeal::model::{self, Model, Operators};
use squeal::petsc::{
    DenseMatrix, DirectPackage, FactoredMatrix, Factorization, LinearMethod, LinearSolver, Runtime,
    RuntimeOptions, Structure,
};
use squeal::study::config::Study;
use std::time::Instant;

fn main() {
    let rt = Runtime::init(&RuntimeOptions::default()).expect("PETSc");
    let comm = rt.world();
    let root = comm.rank() == 0;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let preset = args.first().map_or("small-caliper", String::as_str);
    let block: usize = args.get(1).map_or(32, |b| b.parse().expect("BLOCK"));
    let rounds: usize = args.get(2).map_or(2, |b| b.parse().expect("ROUNDS"));
    let study = Study::builtin(preset);
    let model = Model::from_spec(&study.model_spec()).expect("model");
    let Operators {
        stiffness, mass, ..
    } = model::assemble(comm, &model, MassRule::Exact).expect("assembly");
    let sigma = 0.6 * (2.0 * std::f64::consts::PI * 1e4f64).powi(2);
    let mut a = stiffness.duplicate().expect("copy");
    a.add(-sigma, &mass, Structure::Subset).expect("shift");
    let (lo, hi) = a.ownership_range().expect("rows");
    let n = hi - lo;
    let t = Instant::now();
    let mut single = LinearSolver::new(comm, &a, &LinearMethod::default()).expect("LU");
    let (mut x, b) = a.vectors().expect("vectors");
    let mut b = b;
    b.set_local(&(0..n).map(|i| ((lo + i) as f64).sin()).collect::<Vec<_>>())
        .expect("rhs");
    single.solve(&b, &mut x).expect("first solve");
    let factor_single = t.elapsed().as_secs_f64();
    let t = Instant::now();
    for _ in 0..rounds * block {
        single.solve(&b, &mut x).expect("solve");
    }
    let singles = t.elapsed().as_secs_f64();
    drop(single);
    let t = Instant::now();
    let mut again = LinearSolver::new(comm, &a, &LinearMethod::default()).expect("LU");
    again.solve(&b, &mut x).expect("first solve");
    let factor_again = t.elapsed().as_secs_f64();
    drop(again);
    if root {
        println!("LU and one solve: {factor_single:.2} s, again {factor_again:.2} s");
    }
    let t = Instant::now();
    let factored =
        FactoredMatrix::new(comm, &a, DirectPackage::Mumps, Factorization::Lu).expect("LU");
    let factor_block = t.elapsed().as_secs_f64();
    let mut rhs = DenseMatrix::zeros(comm, n, block).expect("block");
    rhs.write_local(|i, j| ((lo + i) as f64 * (j + 1) as f64).sin())
        .expect("fill");
    let t = Instant::now();
    for _ in 0..rounds {
        let _ = factored.solve_block(&rhs).expect("block solve");
    }
    let blocks = t.elapsed().as_secs_f64();
    let t = Instant::now();
    for _ in 0..rounds {
        let _ = mass.mult_tall(&rhs).expect("mass");
    }
    let products = t.elapsed().as_secs_f64();
    if root {
        println!(
            "{preset}: {} equations; LU {factor_single:.2} s / {factor_block:.2} s; {} single \
             solves {singles:.2} s ({:.4} s each); {rounds} blocks of {block}: {blocks:.2} s \
             ({:.4} s a column); M times a block {:.3} s",
            a.size().expect("size").0,
            rounds * block,
            singles / (rounds * block) as f64,
            blocks / (rounds * block) as f64,
            products / rounds as f64
        );
    }
}
