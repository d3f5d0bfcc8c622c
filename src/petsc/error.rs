//! One error type for everything the PETSc/SLEPc layer can report, carrying PETSc's own
//! message. PETSc's default handler prints a traceback to stderr and returns; we replace it
//! with [`record_error`], which keeps the message so that [`check`] can put it in the `Err`.

use super::sys;
use std::ffi::CStr;
use std::os::raw::{c_char, c_int, c_void};
use std::sync::Mutex;

#[derive(Debug, Clone, thiserror::Error)]
pub enum PetscError {
    /// A PETSc or SLEPc call returned an error code.
    #[error("PETSc error {code}: {message}")]
    Library { code: i32, message: String },
    /// A solver ran but did not converge; `detail` says why and how far it got.
    #[error("{what} did not converge: {detail}")]
    NotConverged { what: String, detail: String },
    /// The wrapper refused a call before it reached C (sizes that do not match...).
    #[error("{0}")]
    Invalid(String),
    /// A Rust callback (SNES residual or Jacobian) failed; its own message.
    #[error("{0}")]
    Callback(String),
}

pub type Result<T> = std::result::Result<T, PetscError>;

/// What the error handler saw for the error in flight: the innermost message and the chain
/// of functions it went up through.
static LAST_ERROR: Mutex<Option<String>> = Mutex::new(None);

fn cstr(p: *const c_char) -> String {
    if p.is_null() {
        String::new()
    } else {
        // SAFETY: PETSc hands the handler NUL-terminated strings that live for the call.
        unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
    }
}

/// The generic text PETSc has for an error code ("Out of memory", "Zero pivot"...).
fn generic_message(code: c_int) -> String {
    let mut text: *const c_char = std::ptr::null();
    // SAFETY: PetscErrorMessage only writes the pointer to a static string.
    unsafe { sys::PetscErrorMessage(code, &mut text, std::ptr::null_mut()) };
    cstr(text)
}

/// PETSc error handler (installed by the runtime): records instead of printing. PETSc calls
/// it once with `PETSC_ERROR_INITIAL` where the error is raised, then with
/// `PETSC_ERROR_REPEAT` in each caller as the error travels up.
pub(super) unsafe extern "C" fn record_error(
    _comm: sys::MPI_Comm,
    line: c_int,
    function: *const c_char,
    file: *const c_char,
    code: sys::PetscErrorCode,
    kind: sys::PetscErrorType,
    message: *const c_char,
    _ctx: *mut c_void,
) -> sys::PetscErrorCode {
    let function = cstr(function);
    let mut last = LAST_ERROR.lock().unwrap_or_else(|e| e.into_inner());
    let initial = kind == sys::PETSC_ERROR_INITIAL;
    match last.as_mut() {
        Some(text) if !initial => {
            text.push_str(" <- ");
            text.push_str(&function);
        }
        _ => {
            let mut text = cstr(message).trim().to_string();
            if text.is_empty() {
                text = generic_message(code);
            }
            let file = cstr(file);
            *last = Some(format!("{text} [{function} at {file}:{line}]"));
        }
    }
    code
}

/// Records a message from the Rust side (a callback that failed) so that the PETSc call
/// that invoked the callback reports it.
pub(super) fn record_callback_error(message: String) {
    *LAST_ERROR.lock().unwrap_or_else(|e| e.into_inner()) = Some(message);
}

/// Turns a PETSc return code into a `Result`, with the message the handler recorded.
pub(super) fn check(code: sys::PetscErrorCode) -> Result<()> {
    if code == 0 {
        return Ok(());
    }
    let message = LAST_ERROR
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .take()
        .unwrap_or_else(|| generic_message(code));
    Err(PetscError::Library { code, message })
}
