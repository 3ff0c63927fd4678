//! The showroom's subject option (CPU side): absent without the scanned head (the APK, a bad
//! or missing head), present with it — in the showroom's corner, a click swaps the subject —
//! and the head, once shown, is framed inside the stage with its credit beside it, lit by
//! the orbiting key light from the chest's distance in play; a run shows the runner again.

use crate::screen;

use std::path::Path;

use dermis_engine::asset::head::CREDIT_LINES;
use dermis_engine::scene::face::HEAD_CENTRE;
use dermis_engine::scene::SceneAssets;
use dermis_engine::scene::{key_light, CHARACTER};
use dermis_engine::ui::Insets;
use dermis_game::app::menu;
use dermis_game::app::showroom::{self, head_matrix, HEAD_HI, HEAD_LO};
use dermis_game::app::{Key, Session, Subject, Viewport};
use dermis_game::rules::Screen;
use glam::Vec3;
use screen::{inside, on_screen};

const FRAME: f32 = 1.0 / 60.0;

fn viewports() -> [Viewport; 3] {
    let vp = |width, height, scale| Viewport {
        width,
        height,
        scale,
        insets: Insets::ZERO,
    };
    [vp(1280, 720, 1.0), vp(640, 360, 1.0), vp(1080, 2340, 2.75)]
}

fn credit_shown(s: &Session) -> bool {
    s.ui.label_rects().any(|(t, _)| t == CREDIT_LINES[0])
}

#[test]
fn without_the_head_there_is_no_subject_option() {
    let model = dermis_engine::asset::shapes::plane_model(0.5, 0.01);
    let mut s = Session::new(&model, 3, None, false);
    s.gui.offer_head(false);
    s.gui.set_subject(Subject::Head);
    s.key(Key::Subject);
    for _ in 0..3 {
        s.update(FRAME, &model, viewports()[0]);
    }
    assert_eq!(s.shown_subject(), Subject::Runner);
    assert_eq!(s.ui.button_rects().count(), 2, "only the model and start");
    assert!(!credit_shown(&s));
    assert!(s.draw_set().props);
}

#[test]
fn a_missing_head_is_no_head_and_no_panic() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets");
    let assets = SceneAssets::load(&root, None).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        assets.head.wait().is_none(),
        "the head is only loaded on request"
    );
    assert!(!assets.head.expected());
    let empty = std::env::temp_dir().join(format!("dermis-no-head-{}", std::process::id()));
    std::fs::create_dir_all(&empty).unwrap();
    assert!(assets.with_head(&empty).head.wait().is_none());
    // A head folder holding a broken mesh.
    std::fs::create_dir_all(empty.join("head")).unwrap();
    std::fs::write(empty.join("head/LeePerrySmith.glb"), b"glTF not really").unwrap();
    let assets = SceneAssets::load(&root, None).unwrap();
    let head = assets.with_head(&empty).head;
    assert!(head.wait().is_none() && !head.expected());
    std::fs::remove_dir_all(&empty).unwrap();
}

#[test]
fn the_head_option_swaps_the_subject_framed_in_the_stage_with_its_credit() {
    let model = dermis_engine::asset::shapes::plane_model(0.5, 0.01);
    for vp in viewports() {
        let mut s = Session::new(&model, 3, None, false);
        s.gui.offer_head(true);
        s.update(FRAME, &model, vp);
        assert_eq!(s.shown_subject(), Subject::Runner);
        assert_eq!(s.ui.button_rects().count(), 3, "{vp:?}");
        let (_, layout) = menu::layout_for(&s.ui, &vp);
        let option = s.ui.button_rects().nth(2).unwrap();
        assert!(inside(&option, &layout.stage), "{vp:?}: {option:?}");
        assert!(!credit_shown(&s));
        // A click (physical pixels) on the option.
        let c = option.center();
        let (x, y) = (c[0] * vp.scale, c[1] * vp.scale);
        s.pointer_down(x, y);
        s.pointer_up(x, y);
        s.update(FRAME, &model, vp);
        assert_eq!(s.gui.subject(), Subject::Head);
        // The frame after the click shows it (the showroom reads the choice first).
        s.update(FRAME, &model, vp);
        assert_eq!(s.shown_subject(), Subject::Head);
        assert!(!s.draw_set().props);
        assert!(credit_shown(&s), "{vp:?}: the head without its credit");
        for (text, r) in s.ui.label_rects() {
            if CREDIT_LINES.contains(&text) {
                assert!(inside(&r, &layout.stage), "{vp:?}: credit {r:?} outside");
            }
        }
        // Framed inside the stage, large.
        let (feet, _) = s.game.player_transform();
        let centre = head_matrix(feet).transform_point3(HEAD_CENTRE);
        assert!((centre - (feet + Vec3::Y * showroom::HEAD_HEIGHT)).length() < 1e-5);
        let r = on_screen(&s, &vp, centre + HEAD_LO, centre + HEAD_HI);
        assert!(
            inside(&r, &layout.stage),
            "{vp:?}: head {r:?} vs {:?}",
            layout.stage
        );
        assert!(
            r.h > 0.5 * layout.stage.h || r.w > 0.5 * layout.stage.w,
            "{vp:?}: head {r:?} small in {:?}",
            layout.stage
        );
        // The key light orbits the head at the distance the play key light is from the chest.
        let reach = (key_light(feet).position - CHARACTER.chest_at(feet)).length();
        let mut angles = Vec::new();
        for _ in 0..240 {
            s.update(FRAME, &model, vp);
            let d = s.light.position - centre;
            assert!(
                (d.length() - reach).abs() < 1e-3,
                "{} vs {reach}",
                d.length()
            );
            assert!(d.y > 0.0, "the light below the head");
            angles.push(d.x.atan2(d.z));
        }
        let turned = angles.last().unwrap() - angles[0];
        assert!(turned.abs() > 0.3, "the light turned {turned} rad in 4 s");
        // The H key switches back and forth, as the option does.
        s.key(Key::Subject);
        assert_eq!(s.gui.subject(), Subject::Runner);
        s.key(Key::Subject);
        assert_eq!(s.gui.subject(), Subject::Head);
        // A run shows the runner (with the props) again.
        s.game.start();
        s.update(FRAME, &model, vp);
        assert_eq!(s.game.screen(), Screen::Play);
        assert_eq!(s.shown_subject(), Subject::Runner);
        assert!(s.draw_set().props && !credit_shown(&s));
    }
}
