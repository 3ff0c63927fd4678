//! The launching intent's extras, read through JNI (the activity's `JavaVM`), so a phone can
//! run unattended:
//!
//! ```sh
//! adb shell am start -n org.dermis.app/android.app.NativeActivity \
//!     --es shading oss --ez autoplay true
//! adb shell am start -n org.dermis.app/android.app.NativeActivity \
//!     --es shading oss --ei soak_seconds 600 --ei target_fps 60
//! ```
//!
//! Also the Game Loop test protocol's intent (action [`TEST_LOOP`], the `scenario` int extra,
//! the results file named by the intent's data URI), the app's external files directory
//! (`getExternalFilesDir(null)`) and opening the data URI for writing
//! (`getContentResolver().openFileDescriptor(uri, "w").detachFd()`).

use android_activity::AndroidApp;
use jni::objects::{JObject, JString};
use jni::{jni_sig, jni_str, Env, JValue, JavaVM};
use std::os::fd::{FromRawFd, OwnedFd};
use std::path::PathBuf;

/// The Game Loop test protocol's action (Firebase Test Lab and other device farms).
pub const TEST_LOOP: &str = "com.google.intent.action.TEST_LOOP";

/// What the intent asked for (absent extras are `None` / `false`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Extras {
    /// `--es shading <name>`: a shading model name (`ShadingModel::from_name`).
    pub shading: Option<String>,
    /// `--ez autoplay true`: the bot plays.
    pub autoplay: bool,
    /// `--ei soak_seconds N`: N > 0 runs a soak of N seconds on autoplay (0: no soak).
    pub soak_seconds: i32,
    /// `--ei target_fps N`: the soak's target frame rate (default 60).
    pub target_fps: i32,
    /// The intent's action (e.g. [`TEST_LOOP`]).
    pub action: Option<String>,
    /// `--ei scenario N`: the Game Loop scenario (only read with the [`TEST_LOOP`] action).
    pub scenario: Option<i32>,
    /// The intent's data URI (`getData().toString()`): the Game Loop's results file.
    pub data: Option<String>,
}

impl Extras {
    /// Whether the intent is a Game Loop test ([`TEST_LOOP`]).
    pub fn is_test_loop(&self) -> bool {
        self.action.as_deref() == Some(TEST_LOOP)
    }
}

/// `obj.name()` for a method without arguments that returns an object.
pub(crate) fn get<'local, 'o, 'sig, 'args>(
    env: &mut Env<'local>,
    obj: impl AsRef<JObject<'o>>,
    name: impl AsRef<jni::strings::JNIStr>,
    sig: impl AsRef<jni::signature::MethodSignature<'sig, 'args>>,
) -> Result<JObject<'local>, jni::errors::Error> {
    env.call_method(obj, name, sig, &[])?.l()
}

/// Runs `f` with the JNI environment and the activity (attached to this thread).
pub(crate) fn with_activity<T>(
    app: &AndroidApp,
    f: impl FnOnce(&mut Env, &JObject) -> Result<T, jni::errors::Error>,
) -> Result<T, jni::errors::Error> {
    // SAFETY: android-activity's pointer to the process's JavaVM, valid for its lifetime.
    let vm = unsafe { JavaVM::from_raw(app.vm_as_ptr().cast()) };
    vm.attach_current_thread(|env| -> Result<T, jni::errors::Error> {
        // SAFETY: a global reference to the NativeActivity, valid until Destroy; wrapping it
        // as a JObject neither deletes nor leaks it.
        let activity = unsafe { JObject::from_raw(env, app.activity_as_ptr().cast()) };
        let r = f(env, &activity);
        if env.exception_check() {
            env.exception_describe();
            env.exception_clear();
        }
        r
    })
}

/// `getExternalFilesDir(null)` (created by the call; readable with `adb pull` on release
/// builds); android-activity's external data path when JNI fails. `None` when there is none.
pub fn external_files_dir(app: &AndroidApp) -> Option<PathBuf> {
    let r = with_activity(app, |env, activity| {
        let file = env
            .call_method(
                activity,
                jni_str!("getExternalFilesDir"),
                jni_sig!("(Ljava/lang/String;)Ljava/io/File;"),
                &[JValue::Object(&JObject::null())],
            )?
            .l()?;
        if file.is_null() {
            return Ok(None);
        }
        let path = get(
            env,
            &file,
            jni_str!("getAbsolutePath"),
            jni_sig!("()Ljava/lang/String;"),
        )?;
        let path = env.cast_local::<JString>(path)?;
        Ok(Some(PathBuf::from(path.try_to_string(env)?)))
    });
    match r {
        Ok(Some(p)) => Some(p),
        Ok(None) => {
            log::warn!("getExternalFilesDir(null) returned null (no shared storage?)");
            app.external_data_path()
        }
        Err(e) => {
            log::warn!("getExternalFilesDir over JNI failed ({e}); using the external data path");
            app.external_data_path()
        }
    }
}

/// The activity's cache directory (`getCacheDir()`), else `<internal data path>/cache`.
pub fn cache_dir(app: &AndroidApp) -> Option<PathBuf> {
    let r = with_activity(app, |env, activity| {
        let file = get(
            env,
            activity,
            jni_str!("getCacheDir"),
            jni_sig!("()Ljava/io/File;"),
        )?;
        if file.is_null() {
            return Ok(None);
        }
        let path = get(
            env,
            &file,
            jni_str!("getAbsolutePath"),
            jni_sig!("()Ljava/lang/String;"),
        )?;
        let path = env.cast_local::<JString>(path)?;
        Ok(Some(PathBuf::from(path.try_to_string(env)?)))
    });
    match r {
        Ok(Some(p)) => Some(p),
        Ok(None) | Err(_) => {
            log::warn!("getCacheDir over JNI gave nothing; using the internal data path");
            app.internal_data_path().map(|d| d.join("cache"))
        }
    }
}

/// The display's refresh rate in Hz (`getWindowManager().getDefaultDisplay()
/// .getRefreshRate()`), or `None` when JNI fails.
pub fn display_refresh_rate(app: &AndroidApp) -> Option<f32> {
    let r = with_activity(app, |env, activity| {
        let wm = get(
            env,
            activity,
            jni_str!("getWindowManager"),
            jni_sig!("()Landroid/view/WindowManager;"),
        )?;
        let display = get(
            env,
            &wm,
            jni_str!("getDefaultDisplay"),
            jni_sig!("()Landroid/view/Display;"),
        )?;
        env.call_method(&display, jni_str!("getRefreshRate"), jni_sig!("()F"), &[])?
            .f()
    });
    match r {
        Ok(hz) if hz.is_finite() && hz > 0.0 => Some(hz),
        Ok(hz) => {
            log::warn!("display refresh rate reported as {hz}");
            None
        }
        Err(e) => {
            log::warn!("display refresh rate over JNI failed: {e}");
            None
        }
    }
}

/// Opens the launching intent's data URI (`content://` or `file://`) for writing:
/// `getContentResolver().openFileDescriptor(getIntent().getData(), "w").detachFd()`.
pub fn open_data_for_write(app: &AndroidApp) -> Result<OwnedFd, String> {
    let fd = with_activity(app, |env, activity| {
        let intent = get(
            env,
            activity,
            jni_str!("getIntent"),
            jni_sig!("()Landroid/content/Intent;"),
        )?;
        if intent.is_null() {
            return Ok(-1);
        }
        let uri = get(
            env,
            &intent,
            jni_str!("getData"),
            jni_sig!("()Landroid/net/Uri;"),
        )?;
        if uri.is_null() {
            return Ok(-1);
        }
        let resolver = get(
            env,
            activity,
            jni_str!("getContentResolver"),
            jni_sig!("()Landroid/content/ContentResolver;"),
        )?;
        let mode = env.new_string("w")?;
        let pfd = env
            .call_method(
                &resolver,
                jni_str!("openFileDescriptor"),
                jni_sig!("(Landroid/net/Uri;Ljava/lang/String;)Landroid/os/ParcelFileDescriptor;"),
                &[JValue::Object(&uri), JValue::Object(&mode)],
            )?
            .l()?;
        if pfd.is_null() {
            return Ok(-1);
        }
        env.call_method(&pfd, jni_str!("detachFd"), jni_sig!("()I"), &[])?
            .i()
    })
    .map_err(|e| format!("openFileDescriptor over JNI: {e}"))?;
    if fd < 0 {
        return Err("the intent has no data URI (or the resolver returned null)".into());
    }
    // SAFETY: detachFd hands the descriptor's ownership to the caller.
    Ok(unsafe { OwnedFd::from_raw_fd(fd) })
}

/// Reads the extras; on any JNI failure logs it and returns no extras.
pub fn read(app: &AndroidApp) -> Extras {
    match try_read(app) {
        Ok(extras) => extras,
        Err(e) => {
            log::warn!("cannot read the intent extras ({e}); running without extras");
            Extras::default()
        }
    }
}

fn try_read(app: &AndroidApp) -> Result<Extras, jni::errors::Error> {
    with_activity(app, |env, activity| {
        let intent = get(
            env,
            activity,
            jni_str!("getIntent"),
            jni_sig!("()Landroid/content/Intent;"),
        )?;
        if intent.is_null() {
            return Ok(Extras::default());
        }
        let shading = string_extra(env, &intent, "shading")?;
        let key = env.new_string("autoplay")?;
        let autoplay = env
            .call_method(
                &intent,
                jni_str!("getBooleanExtra"),
                jni_sig!("(Ljava/lang/String;Z)Z"),
                &[JValue::Object(&key), JValue::Bool(false)],
            )?
            .z()?;
        let soak_seconds = int_extra(env, &intent, "soak_seconds", 0)?;
        let target_fps = int_extra(env, &intent, "target_fps", 60)?;
        let action = get(
            env,
            &intent,
            jni_str!("getAction"),
            jni_sig!("()Ljava/lang/String;"),
        )?;
        let action = if action.is_null() {
            None
        } else {
            Some(env.cast_local::<JString>(action)?.try_to_string(env)?)
        };
        let scenario = if action.as_deref() == Some(TEST_LOOP) {
            Some(int_extra(env, &intent, "scenario", 0)?)
        } else {
            None
        };
        let uri = get(
            env,
            &intent,
            jni_str!("getData"),
            jni_sig!("()Landroid/net/Uri;"),
        )?;
        let data = if uri.is_null() {
            None
        } else {
            let text = get(
                env,
                &uri,
                jni_str!("toString"),
                jni_sig!("()Ljava/lang/String;"),
            )?;
            Some(env.cast_local::<JString>(text)?.try_to_string(env)?)
        };
        Ok(Extras {
            shading,
            autoplay,
            soak_seconds,
            target_fps,
            action,
            scenario,
            data,
        })
    })
}

fn int_extra(
    env: &mut Env,
    intent: &JObject,
    name: &str,
    default: i32,
) -> Result<i32, jni::errors::Error> {
    let key = env.new_string(name)?;
    env.call_method(
        intent,
        jni_str!("getIntExtra"),
        jni_sig!("(Ljava/lang/String;I)I"),
        &[JValue::Object(&key), JValue::Int(default)],
    )?
    .i()
}

fn string_extra(
    env: &mut Env,
    intent: &JObject,
    name: &str,
) -> Result<Option<String>, jni::errors::Error> {
    let key = env.new_string(name)?;
    let value = env
        .call_method(
            intent,
            jni_str!("getStringExtra"),
            jni_sig!("(Ljava/lang/String;)Ljava/lang/String;"),
            &[JValue::Object(&key)],
        )?
        .l()?;
    if value.is_null() {
        return Ok(None);
    }
    let value = env.cast_local::<JString>(value)?;
    Ok(Some(value.try_to_string(env)?))
}
