//! Coulomb friction with stick and slip in the static solver: a block pressed on a block,
//! then pulled along x and released, through a loading history whose every state has a
//! closed form from the block's balance. On 1 and 2 ranks (see `common/harness.rs`).

use crate::common;

use common::harness::Check;
use common::meshes::merge;
use squeal::analysis::restraint;
use squeal::analysis::statics::{self, StaticOptions, StaticProblem, StaticSolution};
use squeal::contact::{
    self, ContactPair, FrictionLaw, PairSettings, SearchOptions, SlidingDirection, SlipHistory,
};
use squeal::fem::springs::{add_ground_springs, GroundSpring};
use squeal::fem::{assemble, DofMap, StructureOptions, Support};
use squeal::mesh::{block::block, Material, Mesh};
use squeal::petsc::{Matrix, Runtime, Vector};

pub const CHECKS: &[Check] = &[Check {
    name: "pulled_block_sticks_slips_and_keeps_its_history",
    run: pulled_block,
    ranks: &[1, 2],
    agreement: 1e-8,
}];

fn e<E: std::fmt::Display>(err: E) -> String {
    err.to_string()
}

const MU: f64 = 0.3;
const PRESSURE: f64 = 1e6;
/// Top face 0.1 x 0.06.
const NORMAL: f64 = PRESSURE * 0.1 * 0.06;
/// The soft spring that holds the top block along x (total, N/m): it takes what friction
/// cannot, so that an equilibrium exists past mu N.
const PULL_SPRING: f64 = 1e7;

struct Rig<'rt> {
    mesh: Mesh,
    dofs: DofMap,
    k: Matrix<'rt>,
    pairs: Vec<ContactPair>,
    springs: Vec<GroundSpring>,
}

fn rig(rt: &Runtime) -> Result<Rig<'_>, String> {
    let comm = rt.world();
    let steel = |name: &str| Material {
        name: name.into(),
        young: 210e9,
        poisson: 0.3,
        density: 7850.0,
    };
    let base = block(
        [-0.02, -0.02, -0.02],
        [0.14, 0.10, 0.02],
        [7, 5, 1],
        steel("base"),
    )
    .map_err(e)?;
    let top = block([0.0, 0.0, 0.0], [0.1, 0.06, 0.02], [6, 4, 1], steel("top")).map_err(e)?;
    let mesh = merge(&base, "base_", &top, "top_");
    let settings = PairSettings {
        name: "top/base".into(),
        friction: MU,
        penalty: None,
        separation: true,
        sliding: SlidingDirection::None,
        law: FrictionLaw::Coulomb {
            stick_stiffness: None,
        },
        calculix: None,
    };
    let pair = contact::node_to_surface(
        &mesh,
        &mesh.surfaces["top_z0"],
        &mesh.surfaces["base_z1"],
        settings,
        &SearchOptions::default(),
    )
    .map_err(e)?;
    let supports = vec![Support {
        name: "base_z0".into(),
        nodes: mesh.node_sets["base_z0"].clone(),
        components: [true; 3],
    }];
    // Along x the soft pull spring on the top block's back face (x = 0); along y a soft
    // spring on a side: the friction alone holds the block while it sticks, the springs give
    // the slipping block an equilibrium.
    let mut springs = Vec::new();
    for (set, d, total) in [
        ("top_x0", [1.0, 0.0, 0.0], PULL_SPRING),
        ("top_y0", [0.0, 1.0, 0.0], 1e7),
    ] {
        let nodes = &mesh.node_sets[set];
        for &n in nodes {
            springs.push(GroundSpring {
                node: n,
                direction: d,
                stiffness: total / nodes.len() as f64,
            });
        }
    }
    let pairs = vec![pair];
    let dofs = DofMap::new(mesh.nodes.len(), 0, &supports, comm.size(), comm.rank()).map_err(e)?;
    let groups = contact::contact_groups(&pairs);
    let pattern = assemble::pattern(
        &dofs,
        mesh.elements
            .iter()
            .map(|c| &c[..])
            .chain(groups.iter().map(|g| &g[..])),
    );
    let (mut k, _m) =
        assemble::stiffness_and_mass(comm, &mesh, &dofs, &pattern, StructureOptions::default())
            .map_err(e)?;
    add_ground_springs(&mut k, &dofs, &springs).map_err(e)?;
    Ok(Rig {
        mesh,
        dofs,
        k,
        pairs,
        springs,
    })
}

impl<'rt> Rig<'rt> {
    /// The pressure on the top face plus a pull `pull` (N, along x) shared by the nodes of
    /// the front face (x = 0.1).
    fn load(&self, rt: &'rt Runtime, pull: f64) -> Result<Vector<'rt>, String> {
        let faces: Vec<_> = self.mesh.surfaces["top_z1"]
            .faces
            .iter()
            .map(|f| (*f, PRESSURE))
            .collect();
        let front = &self.mesh.node_sets["top_x1"];
        let forces: Vec<(usize, usize, f64)> = front
            .iter()
            .map(|&n| (n, 0, pull / front.len() as f64))
            .collect();
        assemble::load_vector(rt.world(), &self.mesh, &self.dofs, &faces, &forces).map_err(e)
    }

    /// The equilibrium under `pull` from a previous one (displacement and slip history).
    fn solve(
        &self,
        rt: &'rt Runtime,
        pull: f64,
        from: Option<&StaticSolution>,
    ) -> Result<StaticSolution, String> {
        let load = self.load(rt, pull)?;
        let no_slip = SlipHistory::default();
        let problem = StaticProblem {
            dofs: &self.dofs,
            stiffness: &self.k,
            load: &load,
            pairs: &self.pairs,
            slip: from.map_or(&no_slip, |s| &s.slip_after),
            bodies: &restraint::bodies(&self.mesh),
            constraints: None,
        };
        statics::solve(
            rt.world(),
            &problem,
            from.map(|s| &s.displacement[..]),
            &StaticOptions::default(),
        )
        .map_err(e)
    }

    /// The pull spring's force on the block along x, `-sum k_i u_x,i`.
    fn spring_force(&self, s: &StaticSolution) -> f64 {
        self.springs
            .iter()
            .filter(|g| g.direction[0] == 1.0)
            .map(|g| -g.stiffness * s.displacement[g.node][0])
            .sum()
    }
}

/// The state of the interface at one step of the history.
struct Step {
    name: &'static str,
    pull: f64,
    summary: contact::PairSummary,
    spring: f64,
    /// Mean x displacement of the top face.
    slide: f64,
    /// sum |f_T| / (mu sum p) over the closed points: 1 when every one is on its cone.
    cone: f64,
}

/// Pressed by 1 MPa (N = 6 kN), then pulled along x by 0.5 mu N (sticks), 1.5 mu N (slips:
/// friction = mu N, the spring takes 0.5 mu N), released to 0 (the spring's 0.5 mu N is now
/// held by friction the other way: the block sticks where it slipped to: hysteresis), and
/// pushed back by -1.5 mu N (slips back: the spring takes -0.5 mu N). At every step the
/// block's balance along x, pull + friction + spring = 0, holds to solver tolerance, and in
/// the slipping steps the friction is mu N exactly (every closed point on its cone).
fn pulled_block(rt: &Runtime) -> Result<Vec<f64>, String> {
    let rig = rig(rt)?;
    let mu_n = MU * NORMAL;
    let history = [
        ("pressed", 0.0),
        ("pulled 0.5 mu N", 0.5 * mu_n),
        ("pulled 1.5 mu N", 1.5 * mu_n),
        ("released", 0.0),
        ("pushed -1.5 mu N", -1.5 * mu_n),
    ];
    let mut steps = Vec::new();
    let mut last: Option<StaticSolution> = None;
    let top_face = &rig.mesh.node_sets["top_z0"];
    for (name, pull) in history {
        let s = rig.solve(rt, pull, last.as_ref())?;
        let summary = contact::summarize_states(&rig.pairs[0], &s.contact[0]);
        let slide =
            top_face.iter().map(|&n| s.displacement[n][0]).sum::<f64>() / top_face.len() as f64;
        let (mut friction_sum, mut normal_sum) = (0.0, 0.0);
        for state in s.contact[0].iter().filter(|p| p.closed) {
            let f = state.friction_force;
            friction_sum += (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
            normal_sum += state.normal_force;
        }
        let step = Step {
            name,
            pull,
            summary,
            spring: rig.spring_force(&s),
            slide,
            cone: friction_sum / (MU * normal_sum),
        };
        if rt.world().rank() == 0 {
            eprintln!(
                "{:>17}: pull {:+.1} N, friction {:+.2} N (mu N = {mu_n:.1}), spring {:+.2} \
                 N, slide {:+.3e} m; {} closed of {}: {} stick, {} slip; {} Newton iterations",
                step.name,
                step.pull,
                step.summary.friction_force[0],
                step.spring,
                step.slide,
                step.summary.closed,
                step.summary.points,
                step.summary.stick,
                step.summary.slip,
                s.increments.iter().map(|i| i.iterations).sum::<usize>()
            );
        }
        steps.push(step);
        last = Some(s);
    }
    for s in &steps {
        // Normal balance and the x balance of the top block. Newton stops at 1e-10 of the
        // initial residual (~ the load): the balances hold to about that.
        let n = s.summary.normal_force;
        if (n - NORMAL).abs() > 1e-8 * NORMAL {
            return Err(format!("{}: normal force {n} vs {NORMAL}", s.name));
        }
        let balance = s.pull + s.summary.friction_force[0] + s.spring;
        if balance.abs() > 1e-8 * NORMAL {
            return Err(format!("{}: x balance off by {balance} N", s.name));
        }
    }
    let [pressed, stuck, slipping, released, back] = &steps[..] else {
        unreachable!()
    };
    // Pressed only: the block's Poisson expansion under the pressure is resisted by the
    // sticking interface, which self-balances but for what the (asymmetric) springs take:
    // under 0.1 % of mu N. Every point sticks.
    if pressed.summary.friction_force[0].abs() > 1e-3 * mu_n
        || pressed.summary.stick != pressed.summary.points
    {
        return Err(format!(
            "pressed: friction {}",
            pressed.summary.friction_force[0]
        ));
    }
    // 0.5 mu N: stick holds the block (the edges, where the pressure is lowest, slip: a
    // partial slip): the stick springs are ~760 times stiffer than the pull spring, so
    // friction carries all but ~0.1 % of the pull.
    let carried = -stuck.summary.friction_force[0] / stuck.pull;
    if !(0.99..=1.0).contains(&carried) || stuck.summary.stick == 0 {
        return Err(format!(
            "0.5 mu N: friction carries {carried} of the pull, {} points stick",
            stuck.summary.stick
        ));
    }
    // Slipping steps: every closed point slips and friction = mu N (its sign against the
    // motion); the spring takes the rest.
    for (s, sign) in [(slipping, -1.0), (back, 1.0)] {
        // Each point's friction is mu p to round-off; their resultant is mu N but for the
        // slight turning of the slip directions (the block's Poisson expansion): 1e-6.
        let f = s.summary.friction_force;
        if s.summary.slip != s.summary.closed
            || (s.cone - 1.0).abs() > 1e-12
            || (f[0] - sign * mu_n).abs() > 1e-6 * mu_n
        {
            return Err(format!(
                "{}: {} of {} closed points slip, friction {f:?} vs mu N = {mu_n}",
                s.name, s.summary.slip, s.summary.closed
            ));
        }
    }
    // Released: the spring pulls back with 0.5 mu N < mu N: friction holds it the other
    // way and the block stays where it slipped to (a law without history would spring
    // back to where it started).
    // The stick springs are ~760 times stiffer than the pull spring: from -mu N to
    // +0.5 mu N of friction the block moves back by 1.5 mu N / K_stick, which relaxes the
    // spring by ~0.2 % of 0.5 mu N.
    if (released.summary.friction_force[0] + slipping.spring).abs() > 1e-2 * mu_n
        || released.summary.stick == 0
        || (released.slide / slipping.slide) < 0.99
    {
        return Err(format!(
            "released: friction {}, slide {} (was {}), {} points stick",
            released.summary.friction_force[0],
            released.slide,
            slipping.slide,
            released.summary.stick
        ));
    }
    // The slides follow from the spring: its nodes' mean x is -spring / k, and the block
    // moves nearly rigidly (its stretch under mu N is ~1e-7 m against slides of ~1e-4 m).
    for s in [slipping, back] {
        let expected = -s.spring / PULL_SPRING;
        if (s.slide - expected).abs() > 1e-2 * expected.abs() {
            return Err(format!(
                "{}: slide {} vs -spring / k = {expected}",
                s.name, s.slide
            ));
        }
    }
    Ok(steps
        .iter()
        .flat_map(|s| [s.summary.friction_force[0], s.spring, s.slide])
        .collect())
}
