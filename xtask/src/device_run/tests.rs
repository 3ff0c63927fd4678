//! `device-run` against a fake `adb` (a shell script answering as a real one does), so the
//! argument handling, the device checks, the polling and every error path run without a phone.

use super::*;

fn args(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

#[test]
fn parses_defaults_and_values() {
    let o = parse_args(&args(&["--serial", "X"])).unwrap().unwrap();
    assert_eq!(
        o,
        Options {
            serial: Some("X".into()),
            ..Options::default()
        }
    );
    assert_eq!((o.seconds, o.shading.as_str(), o.fps), (60, "oss", 60));
    let o = parse_args(&args(&[
        "--seconds",
        "600",
        "--shading",
        "burley",
        "--fps",
        "30",
        "--serial",
        "emulator-5554",
        "--apk",
        "a.apk",
        "--out",
        "o",
        "--startup-timeout",
        "20",
    ]))
    .unwrap()
    .unwrap();
    assert_eq!(o.seconds, 600);
    assert_eq!(o.shading, "burley");
    assert_eq!(o.fps, 30);
    assert_eq!(o.serial.as_deref(), Some("emulator-5554"));
    assert_eq!(o.apk, Some(PathBuf::from("a.apk")));
    assert_eq!(o.out, Some(PathBuf::from("o")));
    assert_eq!(o.startup_timeout, Duration::from_secs(20));
    assert_eq!(parse_args(&args(&["--help"])).unwrap(), None);
}

#[test]
fn rejects_bad_arguments() {
    for (a, want) in [
        (&["--seconds", "0"][..], "not a positive integer"),
        (&["--seconds", "ten"][..], "not a positive integer"),
        (&["--fps"][..], "needs a value"),
        (
            &["--shading", "oss; reboot"][..],
            "not a shading model name",
        ),
        (&["--frobnicate"][..], "unknown argument"),
    ] {
        let e = parse_args(&args(a)).unwrap_err();
        assert!(e.contains(want), "{a:?}: {e}");
    }
}

#[test]
fn picks_the_one_ready_device() {
    let devs =
        parse_devices("* daemon started successfully\nList of devices attached\nR58M\tdevice\n\n");
    assert_eq!(devs, vec![("R58M".to_string(), "device".to_string())]);
    assert_eq!(pick_device(&devs, None).unwrap(), "R58M");
    assert!(pick_device(&[], None).unwrap_err().starts_with("no device"));
    let two = parse_devices("List of devices attached\nA1\tdevice\nemulator-5554\tdevice\n");
    let e = pick_device(&two, None).unwrap_err();
    assert!(e.contains("2 devices") && e.contains("--serial"), "{e}");
    assert_eq!(pick_device(&two, Some("A1")).unwrap(), "A1");
    assert!(pick_device(&two, Some("Z9"))
        .unwrap_err()
        .contains("Z9 not connected"));
    let bad = parse_devices("List of devices attached\nR58M\tunauthorized\n");
    assert!(pick_device(&bad, None)
        .unwrap_err()
        .contains("unauthorized: unlock it"));
    let off = parse_devices("List of devices attached\nR58M\toffline\n");
    assert!(pick_device(&off, Some("R58M"))
        .unwrap_err()
        .contains("offline"));
}

#[test]
fn reads_crashes_and_summaries_from_logcat() {
    let log = "\
11-23 10:00:00.000  4242  4260 I dermis  : soak: adapter: Mali-G57 (Vulkan)
11-23 10:00:00.001  1000  1010 I chatty  : unrelated
11-23 10:00:01.000  4242  4260 F libc    : Fatal signal 11 (SIGSEGV), code 1 in tid 4260 (dermis)
";
    assert_eq!(
        crash_in(log).as_deref(),
        Some("the app crashed (fatal signal)")
    );
    assert_eq!(summary_lines(log), vec!["soak: adapter: Mali-G57 (Vulkan)"]);
    let ex = excerpt(log);
    assert!(ex.contains("Fatal signal") && ex.contains("soak: adapter"));
    assert!(!ex.contains("unrelated"));
    assert!(crash_in("I dermis  : fine\n").is_none());
    let refused =
        "11-23 10:00:00.000  4242  4260 E dermis  : shading \"nope\" is not a model; finishing\n";
    assert_eq!(
        crash_in(refused).unwrap(),
        "the app refused the soak: shading \"nope\" is not a model; finishing"
    );
    assert_eq!(
        report_status(r#"{"status": "running"}"#).as_deref(),
        Some("running")
    );
    assert_eq!(
        report_status("cat: soak.json: No such file or directory"),
        None
    );
}

/// A fake `adb` in its own directory; `mode` picks the behaviour. It appends each call's
/// arguments to `calls` and keeps its state (logcat, poll count) in files beside it.
struct Fake {
    dir: PathBuf,
}

const FAKE_ADB: &str = r#"#!/bin/sh
D="$(dirname "$0")"
MODE="$(cat "$D/mode")"
echo "$*" >> "$D/calls"
if [ "$1" = "-s" ]; then shift 2; fi
log() { echo "11-23 10:00:00.000  4242  4260 $*" >> "$D/logcat"; }
case "$1" in
devices)
    echo "List of devices attached"
    case "$MODE" in
    no-device) ;;
    unauthorized) printf 'R58M\tunauthorized\n' ;;
    two) printf 'A1\tdevice\nB2\tdevice\n' ;;
    *) printf 'R58M\tdevice\n' ;;
    esac
    echo ;;
install)
    echo "Performing Streamed Install"
    if [ "$MODE" = install-refused ]; then
        echo "adb: failed to install $3: Failure [INSTALL_FAILED_UPDATE_INCOMPATIBLE: Package org.dermis.app signatures do not match previously installed version; ignoring!]" >&2
        exit 1
    fi
    echo "Success" ;;
logcat)
    if [ "$2" = "-c" ]; then : > "$D/logcat"; exit 0; fi
    cat "$D/logcat" 2>/dev/null ;;
shell)
    case "$2" in
    am)
        [ "$3" = start ] || exit 0
        echo "Starting: Intent { cmp=org.dermis.app/android.app.NativeActivity (has extras) }"
        if [ "$MODE" = start-error ]; then
            echo "Error type 3"
            echo "Error: Activity class {org.dermis.app/android.app.NativeActivity} does not exist."
            exit 0
        fi
        echo "Status: ok"
        log "I dermis  : soak requested: 60 s, oss at 60 fps"
        if [ "$MODE" = refused ]; then
            log "E dermis  : shading \"nope\" is not a model (known: oss, burley); finishing"
        fi ;;
    rm) ;;
    cat)
        n=$(cat "$D/polls" 2>/dev/null || echo 0); n=$((n + 1)); echo $n > "$D/polls"
        if [ "$MODE" = ok ] && [ $n -ge 40 ]; then
            log "I dermis  : soak: adapter: Mali-G57 MC2 (Vulkan)   2400x1080 target 60 fps (capped), tiers [0]"
            log "I dermis  : soak: 3590 frames in 60.0 s (59.8 fps after 5.0 s warm-up), 3 game runs"
            echo '{"format": "dermis-soak/1", "status": "complete"}'
        elif [ $n -ge 2 ] && [ "$MODE" != gone ]; then
            [ "$MODE" = crash ] && log "F libc    : Fatal signal 11 (SIGSEGV), code 1, fault addr 0x0 in tid 4260 (dermis)"
            echo '{"format": "dermis-soak/1", "status": "running"}'
        else
            echo "cat: /sdcard/Android/data/org.dermis.app/files/soak.json: No such file or directory" >&2
            exit 1
        fi ;;
    pidof) [ "$MODE" = gone ] || echo 4242 ;;
    esac ;;
exec-out) printf '\211PNG\r\n\032\nfake image' ;;
pull)
    echo '{"format": "dermis-soak/1", "status": "complete"}' > "$3"
    echo "$2: 1 file pulled." ;;
*) echo "fake adb: unexpected $*" >&2; exit 1 ;;
esac
"#;

impl Fake {
    fn new(name: &str, mode: &str) -> Self {
        use std::os::unix::fs::PermissionsExt;
        let dir =
            std::env::temp_dir().join(format!("dermis-device-run-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let adb = dir.join("adb");
        std::fs::write(&adb, FAKE_ADB).unwrap();
        std::fs::set_permissions(&adb, std::fs::Permissions::from_mode(0o755)).unwrap();
        std::fs::write(dir.join("mode"), mode).unwrap();
        std::fs::write(dir.join("app.apk"), b"PK fake").unwrap();
        Self { dir }
    }

    fn run(&self, opts: &Options) -> Result<String, String> {
        device_run(
            &self.dir.join("adb"),
            &self.dir.join("app.apk"),
            &self.dir.join("out"),
            opts,
        )
    }

    fn calls(&self) -> String {
        std::fs::read_to_string(self.dir.join("calls")).unwrap_or_default()
    }
}

impl Drop for Fake {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

fn fast() -> Options {
    Options {
        seconds: 1,
        poll: Duration::from_millis(20),
        startup_timeout: Duration::from_secs(30),
        ..Options::default()
    }
}

#[cfg(unix)]
#[test]
fn a_soak_runs_end_to_end() {
    let fake = Fake::new("ok", "ok");
    let out = fake.run(&fast()).unwrap();
    assert!(out.contains("soak complete"), "{out}");
    assert!(out.contains("soak: 3590 frames in 60.0 s"), "{out}");
    assert!(out.contains("screenshot.png"), "{out}");
    let o = fake.dir.join("out");
    assert!(std::fs::read_to_string(o.join("soak.json"))
        .unwrap()
        .contains("\"complete\""));
    assert!(std::fs::read_to_string(o.join("logcat.txt"))
        .unwrap()
        .contains("soak: adapter: Mali-G57"));
    assert!(std::fs::read(o.join("screenshot.png"))
        .unwrap()
        .starts_with(b"\x89PNG"));
    let calls = fake.calls();
    for want in [
        "-s R58M install -r ",
        "-s R58M logcat -c",
        "-s R58M shell am force-stop org.dermis.app",
        "-s R58M shell am start -W -n org.dermis.app/android.app.NativeActivity \
         --ei soak_seconds 1 --es shading oss --ei target_fps 60",
        "-s R58M exec-out screencap -p",
        "-s R58M pull /sdcard/Android/data/org.dermis.app/files/soak.json ",
    ] {
        assert!(calls.contains(want), "missing `{want}` in\n{calls}");
    }
}

#[cfg(unix)]
#[test]
fn a_serial_picks_one_of_several_devices() {
    let fake = Fake::new("two", "two");
    let e = fake.run(&fast()).unwrap_err();
    assert!(
        e.contains("2 devices connected (A1 device, B2 device)"),
        "{e}"
    );
    let e = fake
        .run(&Options {
            serial: Some("B2".into()),
            seconds: 1,
            startup_timeout: Duration::from_secs(1),
            ..fast()
        })
        .unwrap_err();
    // B2 is used (and the fake's soak never completes in this mode).
    assert!(e.starts_with("timed out"), "{e}");
    assert!(fake.calls().contains("-s B2 install -r"));
}

#[cfg(unix)]
#[test]
fn every_failure_is_one_line_and_an_excerpt() {
    let cases = [
        ("no-device", "no device: `adb devices` lists none"),
        ("unauthorized", "device R58M is unauthorized"),
        (
            "install-refused",
            "install refused: adb: failed to install",
        ),
        (
            "start-error",
            "the activity did not start: Error: Activity class {org.dermis.app/android.app.NativeActivity} does not exist.",
        ),
        ("crash", "the app crashed (fatal signal); logcat excerpt:"),
        ("gone", "the app is not running any more after"),
        (
            "refused",
            "the app refused the soak: shading \"nope\" is not a model",
        ),
    ];
    for (mode, want) in cases {
        let fake = Fake::new(mode, mode);
        let e = fake.run(&fast()).unwrap_err();
        assert!(e.starts_with(want), "{mode}: {e}");
        if let Some((first, rest)) = e.split_once('\n') {
            assert!(first.ends_with("logcat excerpt:"), "{mode}: {e}");
            assert!(rest.lines().all(|l| l.starts_with("  ")), "{mode}: {e}");
        }
    }
    let crash = Fake::new("crash2", "crash").run(&fast()).unwrap_err();
    assert!(crash.contains("F libc    : Fatal signal 11"), "{crash}");
    assert!(crash.contains("soak requested"), "{crash}");
    let refused = Fake::new("install-refused2", "install-refused")
        .run(&fast())
        .unwrap_err();
    assert!(
        refused.contains("INSTALL_FAILED_UPDATE_INCOMPATIBLE"),
        "{refused}"
    );
}

#[cfg(unix)]
#[test]
fn times_out_when_the_report_never_completes() {
    let fake = Fake::new("hang", "two");
    let e = fake
        .run(&Options {
            serial: Some("A1".into()),
            startup_timeout: Duration::from_millis(0),
            ..fast()
        })
        .unwrap_err();
    assert!(
        e.starts_with("timed out after 1 s without a complete soak.json"),
        "{e}"
    );
    assert!(e.contains("soak requested"), "{e}");
}

#[test]
fn missing_adb_and_missing_apk_are_clear() {
    let dir = std::env::temp_dir().join(format!("dermis-device-run-{}-none", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let apk = dir.join("app.apk");
    std::fs::write(&apk, b"PK").unwrap();
    let e = device_run(
        &dir.join("no-such-adb"),
        &apk,
        &dir.join("out"),
        &Options::default(),
    )
    .unwrap_err();
    assert!(e.starts_with("adb not found"), "{e}");
    let e = device_run(
        &dir.join("no-such-adb"),
        &dir.join("missing.apk"),
        &dir.join("out"),
        &Options::default(),
    )
    .unwrap_err();
    assert!(e.contains("missing.apk missing"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
