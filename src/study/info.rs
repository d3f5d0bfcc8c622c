//! `squeal info`: what this build of squeal runs on. The first thing a new user runs.

use crate::petsc::{Runtime, RuntimeOptions};
use mpi::traits::{Communicator, Root};

/// One rank's view of the job.
#[derive(Clone, Debug, serde::Serialize)]
pub struct RankView {
    pub rank: usize,
    pub host: String,
    pub pid: u32,
}

/// Everything `squeal info` reports.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Info {
    pub squeal_version: String,
    pub petsc_version: String,
    pub slepc_version: String,
    pub mpi_library: String,
    pub ranks: usize,
    pub index_bytes: usize,
    pub scalar: String,
    /// External packages and whether this PETSc has them.
    pub packages: Vec<(String, bool)>,
    /// The BLAS under MUMPS's dense kernels (rank 0's process).
    pub blas: Option<super::blas::Blas>,
    /// `OPENBLAS_CORETYPE` (squeal's own pin or the user's, [`super::blas_kernel`]); `None`:
    /// the kernel OpenBLAS picked from the CPU.
    pub blas_kernel: Option<String>,
    pub rank_views: Vec<RankView>,
}

const PACKAGES: &[&str] = &[
    "mumps",
    "superlu_dist",
    "hypre",
    "scalapack",
    "suitesparse",
    "ptscotch",
    "metis",
    "parmetis",
    "hdf5",
];

/// Gathers the job's description on rank 0 (collective; `None` on the other ranks).
pub fn gather(rt: &Runtime) -> Result<Option<Info>, super::StudyError> {
    let world = rt.mpi_world();
    let host = mpi::environment::processor_name().unwrap_or_else(|_| "?".into());
    let own = format!("{}\t{}\t{}", world.rank(), host, std::process::id());
    // Fixed-size records keep the gather a plain MPI_Gather of bytes.
    let mut record = [0u8; 256];
    let n = own.len().min(record.len());
    record[..n].copy_from_slice(&own.as_bytes()[..n]);
    let root = world.process_at_rank(0);
    let views = if world.rank() == 0 {
        let mut all = vec![0u8; 256 * world.size() as usize];
        root.gather_into_root(&record[..], &mut all[..]);
        Some(
            all.chunks(256)
                .map(|c| {
                    let text = String::from_utf8_lossy(c)
                        .trim_end_matches('\0')
                        .to_string();
                    let f: Vec<&str> = text.split('\t').collect();
                    RankView {
                        rank: f.first().and_then(|s| s.parse().ok()).unwrap_or(0),
                        host: f.get(1).unwrap_or(&"?").to_string(),
                        pid: f.get(2).and_then(|s| s.parse().ok()).unwrap_or(0),
                    }
                })
                .collect(),
        )
    } else {
        root.gather_into(&record[..]);
        None
    };
    let packages = PACKAGES
        .iter()
        .map(|p| Ok((p.to_string(), rt.has_external_package(p)?)))
        .collect::<crate::petsc::Result<Vec<_>>>()?;
    Ok(views.map(|rank_views| Info {
        squeal_version: env!("CARGO_PKG_VERSION").to_string(),
        petsc_version: rt.petsc_version().unwrap_or_default(),
        slepc_version: rt.slepc_version().unwrap_or_default(),
        mpi_library: mpi::environment::library_version()
            .unwrap_or_default()
            .lines()
            .next()
            .unwrap_or("")
            .trim()
            .to_string(),
        ranks: world.size() as usize,
        index_bytes: rt.index_bytes(),
        scalar: "real double".into(),
        packages,
        blas: super::blas::loaded(),
        blas_kernel: std::env::var("OPENBLAS_CORETYPE").ok(),
        rank_views,
    }))
}

impl std::fmt::Display for Info {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "squeal {}", self.squeal_version)?;
        writeln!(f, "  PETSc        {}", self.petsc_version)?;
        writeln!(f, "  SLEPc        {}", self.slepc_version)?;
        writeln!(f, "  MPI          {}", self.mpi_library)?;
        writeln!(
            f,
            "  scalars      {}, {}-bit indices",
            self.scalar,
            8 * self.index_bytes
        )?;
        let have: Vec<&str> = self
            .packages
            .iter()
            .filter(|p| p.1)
            .map(|p| p.0.as_str())
            .collect();
        let missing: Vec<&str> = self
            .packages
            .iter()
            .filter(|p| !p.1)
            .map(|p| p.0.as_str())
            .collect();
        writeln!(f, "  solvers      {}", have.join(", "))?;
        if !missing.is_empty() {
            writeln!(f, "  not built in {}", missing.join(", "))?;
        }
        match &self.blas {
            Some(b) if b.reference => writeln!(
                f,
                "  BLAS         {} ({}): slow, install libopenblas0-serial",
                b.kind, b.library
            )?,
            Some(b) => match &self.blas_kernel {
                Some(k) => writeln!(f, "  BLAS         {} ({}), kernel {k}", b.kind, b.library)?,
                None => writeln!(f, "  BLAS         {} ({})", b.kind, b.library)?,
            },
            None => writeln!(f, "  BLAS         not found in the process map")?,
        }
        writeln!(f, "  MPI ranks    {}", self.ranks)?;
        for v in &self.rank_views {
            writeln!(f, "    rank {} on {} (pid {})", v.rank, v.host, v.pid)?;
        }
        Ok(())
    }
}

/// Runs `squeal info` (collective); rank 0 prints.
pub fn run(rt: &Runtime, json: bool) -> Result<(), super::StudyError> {
    if let Some(info) = gather(rt)? {
        if json {
            let text =
                serde_json::to_string_pretty(&info).map_err(|source| super::StudyError::Json {
                    what: "squeal info",
                    source,
                })?;
            println!("{text}");
        } else {
            print!("{info}");
        }
    }
    Ok(())
}

/// Default runtime options for a command-line run.
pub fn runtime_options(petsc_options: Option<String>) -> RuntimeOptions {
    RuntimeOptions {
        petsc_options: petsc_options.unwrap_or_default(),
        abort_on_panic: true,
    }
}
