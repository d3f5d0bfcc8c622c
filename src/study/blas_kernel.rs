//! Which OpenBLAS kernel squeal runs on: one of the two its CI checks, where the CPU can run
//! one, rather than whatever OpenBLAS picks from the CPU's model number.
//!
//! Why. OpenBLAS chooses its kernel when it is loaded, from the CPU's vendor and model, and
//! Debian's 0.3.21 gives a model it does not know the SSE3 "Prescott" kernel even where the
//! CPU has AVX-512 (the 2-core Xeons this project's CI has run on): MUMPS's dense blocks then
//! run about 1.4 times slower, and every factorisation rounds in a way no test was run
//! under. The kernels round differently, and squeal's counts and flags (rigid-body modes,
//! unstable modes, contact states) are checked not to flip between SkylakeX and Haswell
//! (`ci/test` runs the deciding tests under both). So when nobody chose a kernel
//! (`OPENBLAS_CORETYPE` unset) and OpenBLAS is the loaded BLAS, `squeal` starts itself again
//! with `OPENBLAS_CORETYPE` set to the best of the two the CPU can execute, before MPI or
//! PETSc start: the kernel is read once, when the library is loaded, so only a new process
//! image can change it. A user's own `OPENBLAS_CORETYPE` is always kept.

/// The kernel to pin in a process whose environment has `coretype` for
/// `OPENBLAS_CORETYPE` and whose BLAS is OpenBLAS (`openblas`), on a CPU with AVX-512
/// (F, CD, BW, DQ, VL: what OpenBLAS's SkylakeX kernels use) or AVX2 with FMA (Haswell's):
/// `None` when the user chose one, the BLAS is another, or the CPU has neither.
pub fn to_pin(
    coretype: Option<&str>,
    openblas: bool,
    avx512: bool,
    avx2: bool,
) -> Option<&'static str> {
    if coretype.is_some() || !openblas {
        return None;
    }
    if avx512 {
        Some("SkylakeX")
    } else if avx2 {
        Some("Haswell")
    } else {
        None
    }
}

/// Whether this CPU runs OpenBLAS's SkylakeX kernels, and its Haswell kernels.
#[cfg(target_arch = "x86_64")]
fn cpu() -> (bool, bool) {
    let avx512 = std::arch::is_x86_feature_detected!("avx512f")
        && std::arch::is_x86_feature_detected!("avx512cd")
        && std::arch::is_x86_feature_detected!("avx512bw")
        && std::arch::is_x86_feature_detected!("avx512dq")
        && std::arch::is_x86_feature_detected!("avx512vl");
    let avx2 =
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma");
    (avx512, avx2)
}

#[cfg(not(target_arch = "x86_64"))]
fn cpu() -> (bool, bool) {
    (false, false)
}

/// The kernel this process should run on and does not yet ([`to_pin`] of its environment,
/// BLAS and CPU).
pub fn wanted() -> Option<&'static str> {
    let coretype = std::env::var("OPENBLAS_CORETYPE").ok();
    let openblas = super::blas::loaded().is_some_and(|b| b.kind == "OpenBLAS");
    let (avx512, avx2) = cpu();
    to_pin(coretype.as_deref(), openblas, avx512, avx2)
}

/// Starts this program again with `OPENBLAS_CORETYPE` = [`wanted`], the same arguments and
/// the rest of the environment, when a kernel is wanted; returns only when none is, or when
/// the new image could not be started (then why, for the log: squeal goes on with the
/// kernel OpenBLAS chose).
pub fn pin() -> Option<String> {
    use std::os::unix::process::CommandExt;
    let kernel = wanted()?;
    let exe = match std::env::current_exe() {
        Ok(exe) => exe,
        Err(e) => {
            return Some(format!(
                "cannot find this program to pin OpenBLAS's {kernel} kernel: {e}"
            ))
        }
    };
    let mut args = std::env::args_os();
    let mut command = std::process::Command::new(&exe);
    if let Some(name) = args.next() {
        command.arg0(name);
    }
    let error = command.args(args).env("OPENBLAS_CORETYPE", kernel).exec();
    Some(format!(
        "cannot start {} again with OpenBLAS's {kernel} kernel ({error}): going on with the kernel \
         OpenBLAS chose",
        exe.display()
    ))
}

#[cfg(test)]
mod tests {
    use super::to_pin;

    #[test]
    fn a_users_kernel_and_other_blas_are_left_alone_and_the_best_tested_one_is_pinned() {
        assert_eq!(to_pin(None, true, true, true), Some("SkylakeX"));
        assert_eq!(to_pin(None, true, false, true), Some("Haswell"));
        assert_eq!(to_pin(None, true, false, false), None);
        assert_eq!(to_pin(Some("Prescott"), true, true, true), None);
        assert_eq!(to_pin(Some(""), true, true, true), None);
        assert_eq!(to_pin(None, false, true, true), None);
    }
}
