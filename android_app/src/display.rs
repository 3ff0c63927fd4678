//! The display's safe area and immersive mode, over JNI (NativeActivity has no Java code).
//!
//! - [`safe_insets`]: the larger of the system-window insets (status/navigation bars, API 20+)
//!   and the display cutout's safe insets (API 28+), in physical pixels, for `Ui::begin`: the
//!   UI anchors every widget inside the safe area (`game/tests/game/ui_safe_area.rs`). Any JNI
//!   failure (an older API, no attached view yet) gives zero insets and one log line.
//! - [`enter_immersive`]: hides the system bars, shown again transiently by a swipe (API 30+
//!   `WindowInsetsController`); older devices keep the theme's full screen (status bar hidden,
//!   navigation bar shown). The activity's theme lays the window out under short-edge
//!   cutouts (`res/values-v28/styles.xml`).

use android_activity::AndroidApp;
use dermis_engine::ui::Insets;
use jni::objects::JObject;
use jni::{jni_sig, jni_str, Env, JValue};

use crate::intent::{get, with_activity};

/// `WindowInsetsController.BEHAVIOR_SHOW_TRANSIENT_BARS_BY_SWIPE`.
const BEHAVIOR_SHOW_TRANSIENT_BARS_BY_SWIPE: i32 = 2;

/// The activity's `Window`.
fn window<'local>(
    env: &mut Env<'local>,
    activity: &JObject,
) -> Result<JObject<'local>, jni::errors::Error> {
    get(
        env,
        activity,
        jni_str!("getWindow"),
        jni_sig!("()Landroid/view/Window;"),
    )
}

/// The decor view's current `WindowInsets` (null before the view is attached).
fn root_insets<'local>(
    env: &mut Env<'local>,
    activity: &JObject,
) -> Result<JObject<'local>, jni::errors::Error> {
    let window = window(env, activity)?;
    let decor = get(
        env,
        &window,
        jni_str!("getDecorView"),
        jni_sig!("()Landroid/view/View;"),
    )?;
    get(
        env,
        &decor,
        jni_str!("getRootWindowInsets"),
        jni_sig!("()Landroid/view/WindowInsets;"),
    )
}

/// [left, top, right, bottom] from four `()I` getters of `obj`.
fn four(
    env: &mut Env,
    obj: &JObject,
    names: [&jni::strings::JNIStr; 4],
) -> Result<[f32; 4], jni::errors::Error> {
    let mut out = [0.0f32; 4];
    for (o, name) in out.iter_mut().zip(names) {
        *o = env.call_method(obj, name, jni_sig!("()I"), &[])?.i()? as f32;
    }
    Ok(out)
}

/// The safe-area insets in physical pixels; zero where they cannot be read.
pub fn safe_insets(app: &AndroidApp) -> Insets {
    let r = with_activity(app, |env, activity| {
        let insets = root_insets(env, activity)?;
        if insets.is_null() {
            return Ok([0.0; 4]);
        }
        let mut edges = four(
            env,
            &insets,
            [
                jni_str!("getSystemWindowInsetLeft"),
                jni_str!("getSystemWindowInsetTop"),
                jni_str!("getSystemWindowInsetRight"),
                jni_str!("getSystemWindowInsetBottom"),
            ],
        )?;
        // API 28+: the cutout's safe insets (NoSuchMethodError before: cleared, ignored).
        let cutout = env.call_method(
            &insets,
            jni_str!("getDisplayCutout"),
            jni_sig!("()Landroid/view/DisplayCutout;"),
            &[],
        );
        match cutout.and_then(|c| c.l()) {
            Ok(c) if !c.is_null() => {
                let safe = four(
                    env,
                    &c,
                    [
                        jni_str!("getSafeInsetLeft"),
                        jni_str!("getSafeInsetTop"),
                        jni_str!("getSafeInsetRight"),
                        jni_str!("getSafeInsetBottom"),
                    ],
                )?;
                for (e, s) in edges.iter_mut().zip(safe) {
                    *e = e.max(s);
                }
            }
            Ok(_) => {}
            Err(_) => env.exception_clear(),
        }
        Ok(edges)
    });
    match r {
        Ok([left, top, right, bottom]) => Insets {
            left,
            top,
            right,
            bottom,
        },
        Err(e) => {
            log::warn!("safe-area insets unavailable ({e}); laying the UI out edge to edge");
            Insets::ZERO
        }
    }
}

/// Immersive sticky mode where the device has `WindowInsetsController` (API 30+).
pub fn enter_immersive(app: &AndroidApp) {
    let r = with_activity(app, |env, activity| {
        let window = window(env, activity)?;
        let controller = get(
            env,
            &window,
            jni_str!("getInsetsController"),
            jni_sig!("()Landroid/view/WindowInsetsController;"),
        )?;
        if controller.is_null() {
            return Ok(());
        }
        let bars = env
            .call_static_method(
                jni_str!("android/view/WindowInsets$Type"),
                jni_str!("systemBars"),
                jni_sig!("()I"),
                &[],
            )?
            .i()?;
        env.call_method(
            &controller,
            jni_str!("setSystemBarsBehavior"),
            jni_sig!("(I)V"),
            &[JValue::Int(BEHAVIOR_SHOW_TRANSIENT_BARS_BY_SWIPE)],
        )?;
        env.call_method(
            &controller,
            jni_str!("hide"),
            jni_sig!("(I)V"),
            &[JValue::Int(bars)],
        )?;
        Ok(())
    });
    if let Err(e) = r {
        log::info!("immersive mode unavailable ({e}); keeping the theme's full screen");
    }
}
