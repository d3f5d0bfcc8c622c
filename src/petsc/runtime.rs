//! The one owner of MPI and PETSc/SLEPc for a process: initialises them in order, finalises
//! them in reverse on `Drop`, and makes a failure on one rank stop every rank.

use super::error::{check, record_error, PetscError, Result};
use super::sys;
use mpi::collective::SystemOperation;
use mpi::topology::{Communicator, SimpleCommunicator};
use mpi::traits::{AsRaw, CommunicatorCollectives, Root};
use std::ffi::{CStr, CString};
use std::os::raw::c_char;

/// How to start the runtime.
#[derive(Clone, Debug, Default)]
pub struct RuntimeOptions {
    /// PETSc options as one string (`"-eps_view -mat_mumps_icntl_14 50"`), passed to PETSc
    /// as its argv. `PETSC_OPTIONS` in the environment is read by PETSc itself as well.
    pub petsc_options: String,
    /// Install a panic hook that aborts every rank (use in programs run under mpirun; a
    /// panic on one rank otherwise leaves the others waiting in a collective call).
    pub abort_on_panic: bool,
}

/// MPI + PETSc + SLEPc, alive for as long as this value is. Every PETSc object borrows it
/// (through [`Comm`]), so none can outlive `SlepcFinalize`.
pub struct Runtime {
    universe: Option<mpi::environment::Universe>,
    world: SimpleCommunicator,
    self_comm: SimpleCommunicator,
    // PETSc keeps pointers into argv for its whole life.
    _argv: Vec<CString>,
    _argv_ptrs: Vec<*mut c_char>,
}

/// A communicator tied to the runtime: what PETSc objects are created on. It carries rsmpi's
/// communicator (owned by the [`Runtime`]), so reductions on plain Rust data go through
/// rsmpi's safe collectives and the raw handle PETSc needs is the same communicator.
#[derive(Clone, Copy)]
pub struct Comm<'rt> {
    pub(super) raw: sys::MPI_Comm,
    mpi: &'rt SimpleCommunicator,
    /// This process alone (the runtime's MPI_COMM_SELF), for [`Comm::alone`].
    alone: &'rt SimpleCommunicator,
    rank: usize,
    size: usize,
}

impl<'rt> Comm<'rt> {
    fn new(mpi: &'rt SimpleCommunicator, alone: &'rt SimpleCommunicator) -> Comm<'rt> {
        Comm {
            raw: mpi.as_raw(),
            mpi,
            alone,
            rank: mpi.rank() as usize,
            size: mpi.size() as usize,
        }
    }

    /// This process alone: where a rank's own sequential PETSc objects live (a dense
    /// reduced model's eigensolve on rank 0, a rank's own copy of a factor).
    pub fn alone(&self) -> Comm<'rt> {
        Comm::new(self.alone, self.alone)
    }

    /// This process's rank in the communicator.
    pub fn rank(&self) -> usize {
        self.rank
    }
    /// Number of ranks in the communicator.
    pub fn size(&self) -> usize {
        self.size
    }
    /// The raw handle, for rsmpi collectives on the same communicator.
    pub fn raw(&self) -> sys::MPI_Comm {
        self.raw
    }
    /// rsmpi's view of this communicator, for collectives on plain Rust data.
    pub fn mpi(&self) -> &'rt SimpleCommunicator {
        self.mpi
    }

    /// The value of a PETSc option in the global database (`-st_matmode` -> "inplace"), `None`
    /// where it is not given, `Some("")` for an option given without a value. The database
    /// comes from the same command line and environment on every rank.
    pub fn option(&self, name: &CStr) -> Result<Option<String>> {
        let mut buf = [0 as c_char; 256];
        let mut set = sys::PETSC_FALSE;
        // SAFETY: the global database (null), no prefix (null), a NUL-terminated name, and a
        // buffer PETSc writes at most len bytes of, NUL-terminated.
        check(unsafe {
            sys::PetscOptionsGetString(
                std::ptr::null_mut(),
                std::ptr::null(),
                name.as_ptr(),
                buf.as_mut_ptr(),
                buf.len(),
                &mut set,
            )
        })?;
        if set != sys::PETSC_TRUE {
            return Ok(None);
        }
        // SAFETY: PETSc NUL-terminated what it wrote.
        Ok(Some(
            unsafe { CStr::from_ptr(buf.as_ptr()) }
                .to_string_lossy()
                .into_owned(),
        ))
    }

    // The reductions below go through rsmpi's safe collectives, which return no error code:
    // squeal installs no MPI error handler of its own, so under MPI's default
    // (MPI_ERRORS_ARE_FATAL) a failed collective aborts the job rather than returning.

    /// Whether `flag` holds on every rank (collective). Used before a collective PETSc call
    /// so that a failure seen by one rank stops all of them instead of leaving the others
    /// waiting.
    pub fn all(&self, flag: bool) -> bool {
        let mut global = false;
        self.mpi
            .all_reduce_into(&flag, &mut global, SystemOperation::logical_and());
        global
    }

    /// Waits until every rank has come here (collective).
    pub fn barrier(&self) {
        self.mpi.barrier();
    }

    /// Element-wise sum of `values` over all ranks, in place (collective).
    pub fn sum_in_place(&self, values: &mut [f64]) {
        let local = values.to_vec();
        self.mpi
            .all_reduce_into(&local[..], values, SystemOperation::sum());
    }

    /// Element-wise sum of `values` over all ranks, in place, with rank 0's bits on every
    /// rank (collective): an all-reduce may associate the sums differently on different
    /// ranks, and the ranks take decisions from these numbers.
    pub fn sum_identically(&self, values: &mut Vec<f64>) {
        self.sum_in_place(values);
        self.broadcast_from_root(values);
    }

    /// Element-wise maximum over all ranks, in place (collective).
    pub fn max_in_place(&self, values: &mut [f64]) {
        let local = values.to_vec();
        self.mpi
            .all_reduce_into(&local[..], values, SystemOperation::max());
    }

    /// The message of the lowest rank that has one, with that rank, on every rank
    /// (collective): how a failure seen by one rank is reported whole by whichever rank
    /// prints, instead of "failed elsewhere".
    pub fn first_message(&self, local: Option<String>) -> Option<(usize, String)> {
        let mine = if local.is_some() {
            self.rank as u64
        } else {
            self.size as u64
        };
        let mut first = 0u64;
        self.mpi
            .all_reduce_into(&mine, &mut first, SystemOperation::min());
        if first as usize >= self.size {
            return None;
        }
        let root = self.mpi.process_at_rank(first as i32);
        let mut bytes = local.unwrap_or_default().into_bytes();
        let mut length = bytes.len() as u64;
        root.broadcast_into(&mut length);
        bytes.resize(length as usize, 0);
        root.broadcast_into(&mut bytes[..]);
        Some((first as usize, String::from_utf8_lossy(&bytes).into_owned()))
    }

    /// Rank 0's `values` on every rank, whatever their length there (collective): how a
    /// result computed once on rank 0 (a dense reduced model's) reaches the others, so that
    /// every rank takes the same decisions from the same bits.
    pub fn broadcast_from_root(&self, values: &mut Vec<f64>) {
        let root = self.mpi.process_at_rank(0);
        let mut length = values.len() as u64;
        root.broadcast_into(&mut length);
        values.resize(length as usize, 0.0);
        root.broadcast_into(&mut values[..]);
    }

    /// Rank 0's `bytes` on every rank (collective): a record rank 0 read from disk (a
    /// resumed sweep's checkpoint), so that no other rank needs to see rank 0's files.
    pub fn broadcast_bytes_from_root(&self, bytes: &mut Vec<u8>) {
        let root = self.mpi.process_at_rank(0);
        let mut length = bytes.len() as u64;
        root.broadcast_into(&mut length);
        bytes.resize(length as usize, 0);
        root.broadcast_into(&mut bytes[..]);
    }
}

impl Runtime {
    /// Initialises MPI, then SLEPc (which initialises PETSc) on MPI_COMM_WORLD.
    /// Collective over all processes of the job. Fails if MPI is already initialised.
    pub fn init(options: &RuntimeOptions) -> Result<Runtime> {
        let universe = mpi::initialize()
            .ok_or_else(|| PetscError::Invalid("MPI was already initialised".into()))?;
        let world = universe.world();
        // PETSc's signal handler would replace Rust's (a broken pipe would MPI_Abort the job).
        let mut args = vec!["squeal".to_string(), "-no_signal_handler".to_string()];
        args.extend(options.petsc_options.split_whitespace().map(String::from));
        let argv: Vec<CString> = args
            .into_iter()
            .map(|a| {
                CString::new(a).map_err(|_| PetscError::Invalid("NUL in a PETSc option".into()))
            })
            .collect::<Result<_>>()?;
        let mut argv_ptrs: Vec<*mut c_char> =
            argv.iter().map(|a| a.as_ptr() as *mut c_char).collect();
        argv_ptrs.push(std::ptr::null_mut());
        let mut argc = (argv_ptrs.len() - 1) as i32;
        let mut argv_p = argv_ptrs.as_mut_ptr();
        // SAFETY: MPI is initialised; PETSC_COMM_WORLD must be set before PetscInitialize and
        // nothing else touches it concurrently. argv lives as long as the Runtime.
        unsafe {
            sys::PETSC_COMM_WORLD = world.as_raw();
            check(sys::SlepcInitialize(
                &mut argc,
                &mut argv_p,
                std::ptr::null(),
                std::ptr::null(),
            ))?;
            check(sys::PetscPushErrorHandler(
                Some(record_error),
                std::ptr::null_mut(),
            ))?;
        }
        if options.abort_on_panic && world.size() > 1 {
            install_abort_on_panic();
        }
        Ok(Runtime {
            universe: Some(universe),
            world,
            self_comm: SimpleCommunicator::self_comm(),
            _argv: argv,
            _argv_ptrs: argv_ptrs,
        })
    }

    /// All ranks of the job.
    pub fn world(&self) -> Comm<'_> {
        Comm::new(&self.world, &self.self_comm)
    }

    /// This rank alone (for per-rank sequential objects).
    pub fn self_comm(&self) -> Comm<'_> {
        Comm::new(&self.self_comm, &self.self_comm)
    }

    /// rsmpi's view of the world communicator, for collectives on plain Rust data.
    pub fn mpi_world(&self) -> &SimpleCommunicator {
        &self.world
    }

    /// Stops every rank of the job with `code`. Use on a fatal error that only this rank
    /// knows about, where returning would leave the others waiting in a collective.
    pub fn abort(&self, code: i32) -> ! {
        self.world.abort(code)
    }

    /// PETSc's version string, e.g. "Petsc Release Version 3.18.5, ...".
    pub fn petsc_version(&self) -> Result<String> {
        let mut buf = [0 as c_char; 256];
        // SAFETY: PETSc writes at most len bytes, NUL-terminated.
        check(unsafe { sys::PetscGetVersion(buf.as_mut_ptr(), buf.len()) })?;
        Ok(unsafe { CStr::from_ptr(buf.as_ptr()) }
            .to_string_lossy()
            .into_owned())
    }

    /// SLEPc's version string.
    pub fn slepc_version(&self) -> Result<String> {
        let mut buf = [0 as c_char; 256];
        // SAFETY: as above.
        check(unsafe { sys::SlepcGetVersion(buf.as_mut_ptr(), buf.len()) })?;
        Ok(unsafe { CStr::from_ptr(buf.as_ptr()) }
            .to_string_lossy()
            .into_owned())
    }

    /// Whether PETSc was configured with an external package ("mumps", "superlu_dist"...).
    pub fn has_external_package(&self, name: &str) -> Result<bool> {
        let name = CString::new(name).map_err(|_| PetscError::Invalid("NUL in name".into()))?;
        let mut has = sys::PETSC_FALSE;
        // SAFETY: valid string, out-pointer to a local.
        check(unsafe { sys::PetscHasExternalPackage(name.as_ptr(), &mut has) })?;
        Ok(has == sys::PETSC_TRUE)
    }

    /// Bytes in a PetscInt in the linked PETSc (4 or 8).
    pub fn index_bytes(&self) -> usize {
        std::mem::size_of::<sys::PetscInt>()
    }
}

impl Drop for Runtime {
    fn drop(&mut self) {
        // SAFETY: every PETSc object borrows the runtime, so all are destroyed by now.
        // SlepcFinalize also finalises PETSc and leaves MPI to rsmpi's Universe.
        unsafe { sys::SlepcFinalize() };
        self.universe.take();
    }
}

/// On a panic, print the usual message and then abort the whole MPI job, so the other ranks
/// do not wait forever in a collective call.
fn install_abort_on_panic() {
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        previous(info);
        eprintln!("squeal: a rank panicked; aborting all ranks");
        // SAFETY: MPI is initialised while the runtime lives; MPI_Abort does not return.
        unsafe { sys::MPI_Abort(sys::RSMPI_COMM_WORLD, 101) };
    }));
}
