//! The launching intent's extras, read through JNI (the activity's `JavaVM`), so a phone can
//! run unattended:
//!
//! ```sh
//! adb shell am start -n org.dermis.app/android.app.NativeActivity \
//!     --es shading oss --ez autoplay true
//! ```

use android_activity::AndroidApp;
use jni::objects::{JObject, JString};
use jni::{jni_sig, jni_str, Env, JValue, JavaVM};

/// What the intent asked for (absent extras are `None` / `false`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Extras {
    /// `--es shading <name>`: a shading model name (`ShadingModel::from_name`).
    pub shading: Option<String>,
    /// `--ez autoplay true`: the bot plays.
    pub autoplay: bool,
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
    // SAFETY: android-activity's pointer to the process's JavaVM, valid for its lifetime.
    let vm = unsafe { JavaVM::from_raw(app.vm_as_ptr().cast()) };
    vm.attach_current_thread(|env| -> Result<Extras, jni::errors::Error> {
        // SAFETY: a global reference to the NativeActivity, valid until Destroy; wrapping it
        // as a JObject neither deletes nor leaks it.
        let activity = unsafe { JObject::from_raw(env, app.activity_as_ptr().cast()) };
        let intent = env
            .call_method(
                &activity,
                jni_str!("getIntent"),
                jni_sig!("()Landroid/content/Intent;"),
                &[],
            )?
            .l()?;
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
        Ok(Extras { shading, autoplay })
    })
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
