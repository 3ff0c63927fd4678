//! NDK functions newer than the app's minSdk (26), resolved at run time with
//! `dlopen("libandroid.so")` / `dlsym` — never linked, so the library loads on API 26 and
//! every import stays in the API ≤ 26 table. Each absent function is logged once (when the
//! table is first used) and its feature skipped.
//!
//! - API 30: `AThermal_acquireManager`, `AThermal_releaseManager`,
//!   `AThermal_getCurrentThermalStatus`, `ANativeWindow_setFrameRate`;
//! - API 31: `AThermal_getThermalHeadroom`;
//! - API 33: `APerformanceHint_getManager`, `APerformanceHint_createSession`,
//!   `APerformanceHint_reportActualWorkDuration`, `APerformanceHint_closeSession`.

use std::ffi::{c_void, CStr};
use std::sync::OnceLock;

type Ptr = *mut c_void;

/// The resolved functions (`None`: not in this device's libandroid.so).
pub struct Ndk {
    pub thermal_acquire: Option<unsafe extern "C" fn() -> Ptr>,
    pub thermal_release: Option<unsafe extern "C" fn(Ptr)>,
    pub thermal_status: Option<unsafe extern "C" fn(Ptr) -> i32>,
    pub thermal_headroom: Option<unsafe extern "C" fn(Ptr, i32) -> f32>,
    pub set_frame_rate: Option<unsafe extern "C" fn(Ptr, f32, i8) -> i32>,
    pub hint_manager: Option<unsafe extern "C" fn() -> Ptr>,
    pub hint_create: Option<unsafe extern "C" fn(Ptr, *const i32, usize, i64) -> Ptr>,
    pub hint_report: Option<unsafe extern "C" fn(Ptr, i64) -> i32>,
    pub hint_close: Option<unsafe extern "C" fn(Ptr)>,
}

// SAFETY: plain function pointers into libandroid.so (never unloaded).
unsafe impl Send for Ndk {}
unsafe impl Sync for Ndk {}

/// # Safety
/// `F` must be the `unsafe extern "C" fn` type of the symbol `name`.
unsafe fn sym<F: Copy>(lib: Ptr, name: &CStr) -> Option<F> {
    debug_assert_eq!(std::mem::size_of::<F>(), std::mem::size_of::<Ptr>());
    let p = if lib.is_null() {
        std::ptr::null_mut()
    } else {
        libc::dlsym(lib, name.as_ptr())
    };
    if p.is_null() {
        log::info!(
            "{} is not available on this device: skipped",
            name.to_string_lossy()
        );
        None
    } else {
        Some(std::mem::transmute_copy::<Ptr, F>(&p))
    }
}

/// The table, resolved on first use.
pub fn get() -> &'static Ndk {
    static NDK: OnceLock<Ndk> = OnceLock::new();
    NDK.get_or_init(|| {
        // SAFETY: dlopen of a system library with a NUL-terminated name; the handle is kept
        // for the process's lifetime. Each symbol is given its NDK header's signature.
        unsafe {
            let lib = libc::dlopen(c"libandroid.so".as_ptr(), libc::RTLD_NOW);
            if lib.is_null() {
                log::warn!("dlopen(libandroid.so) failed: API 30+ functions skipped");
            }
            Ndk {
                thermal_acquire: sym(lib, c"AThermal_acquireManager"),
                thermal_release: sym(lib, c"AThermal_releaseManager"),
                thermal_status: sym(lib, c"AThermal_getCurrentThermalStatus"),
                thermal_headroom: sym(lib, c"AThermal_getThermalHeadroom"),
                set_frame_rate: sym(lib, c"ANativeWindow_setFrameRate"),
                hint_manager: sym(lib, c"APerformanceHint_getManager"),
                hint_create: sym(lib, c"APerformanceHint_createSession"),
                hint_report: sym(lib, c"APerformanceHint_reportActualWorkDuration"),
                hint_close: sym(lib, c"APerformanceHint_closeSession"),
            }
        }
    })
}

/// `ANativeWindow_setFrameRate(window, fps, ANATIVEWINDOW_FRAME_RATE_COMPATIBILITY_DEFAULT)`.
pub fn set_frame_rate(window: *mut c_void, fps: f32) {
    let Some(f) = get().set_frame_rate else {
        return;
    };
    // SAFETY: `window` is a live ANativeWindow (the caller holds a reference).
    let r = unsafe { f(window, fps, 0) };
    if r == 0 {
        log::info!("ANativeWindow_setFrameRate({fps}) accepted");
    } else {
        log::warn!("ANativeWindow_setFrameRate({fps}) returned {r}");
    }
}

/// An API 33 performance-hint session for the calling thread (closed on drop).
pub struct HintSession {
    session: Ptr,
    report: unsafe extern "C" fn(Ptr, i64) -> i32,
    close: Option<unsafe extern "C" fn(Ptr)>,
    failed_reports: u64,
}

impl HintSession {
    /// For the calling thread with the target work duration `target_ns`; `None` where the
    /// API is missing or the session cannot be created.
    pub fn for_this_thread(target_ns: i64) -> Option<Self> {
        let ndk = get();
        let (manager, create, report) = (ndk.hint_manager?, ndk.hint_create?, ndk.hint_report?);
        // SAFETY: API 33 functions with their NDK signatures; the thread id array outlives
        // the call.
        unsafe {
            let m = manager();
            if m.is_null() {
                log::warn!("APerformanceHint_getManager returned null");
                return None;
            }
            let tid = libc::gettid();
            let session = create(m, &tid, 1, target_ns);
            if session.is_null() {
                log::warn!("APerformanceHint_createSession failed (hint sessions unsupported?)");
                return None;
            }
            log::info!("performance hint session for thread {tid}, target {target_ns} ns");
            Some(Self {
                session,
                report,
                close: ndk.hint_close,
                failed_reports: 0,
            })
        }
    }

    /// Reports one frame's actual work duration.
    pub fn report(&mut self, actual_ns: i64) {
        // SAFETY: a live session.
        let r = unsafe { (self.report)(self.session, actual_ns.max(1)) };
        if r != 0 {
            self.failed_reports += 1;
            if self.failed_reports == 1 {
                log::warn!("APerformanceHint_reportActualWorkDuration returned {r}");
            }
        }
    }
}

impl Drop for HintSession {
    fn drop(&mut self) {
        if let Some(close) = self.close {
            // SAFETY: the session is live and closed once.
            unsafe { close(self.session) };
        }
    }
}

/// Thermal status and headroom, read by [`thermal_sample`].
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct ThermalSample {
    pub t_s: f64,
    /// `AThermalStatus`: 0 none, 1 light, 2 moderate, 3 severe, 4 critical, 5 emergency,
    /// 6 shutdown; -1 error; `None` without the API.
    pub status: Option<i32>,
    /// `AThermal_getThermalHeadroom(0)`: 1.0 = severe throttling; NaN (null) when polled
    /// faster than the platform allows or unsupported; `None` without the API (31).
    pub headroom: Option<f32>,
}

/// A thermal manager (API 30), released on drop. Lives on the sampling thread.
pub struct Thermal(Ptr);

impl Thermal {
    pub fn acquire() -> Option<Self> {
        let f = get().thermal_acquire?;
        // SAFETY: API 30 function, no arguments.
        let m = unsafe { f() };
        (!m.is_null()).then_some(Thermal(m))
    }

    pub fn sample(&self, t_s: f64) -> ThermalSample {
        let ndk = get();
        // SAFETY: a live manager; NDK signatures.
        unsafe {
            ThermalSample {
                t_s,
                status: ndk.thermal_status.map(|f| f(self.0)),
                headroom: ndk.thermal_headroom.map(|f| f(self.0, 0)),
            }
        }
    }
}

impl Drop for Thermal {
    fn drop(&mut self) {
        if let Some(f) = get().thermal_release {
            // SAFETY: the manager is live and released once.
            unsafe { f(self.0) };
        }
    }
}
