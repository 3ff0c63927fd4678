//! KTX2 texture files, good and hostile (`tests/data/ktx2/`): a good file reads as it was
//! written; a truncated one, one lying about its size or its levels, one in a format dermis
//! does not read or in the wrong colour space for its role, is one line of error and never a
//! panic, and the loader then falls back (another encoding, else the decoded source; a KTX2
//! image in the other role's colour space, to that role's encodings beside it). Runs on
//! Android bionic too (`cargo xtask android-test`).

use crate::external;

use std::path::PathBuf;

use dermis_engine::asset::compressed::{encoded_texture, fnv1a64, full_chain, level_size, LIMITS};
use dermis_engine::asset::{BlockFormat, BlockImage, Family, Texels, TextureRole};

fn dir() -> PathBuf {
    external::data_dir().join("ktx2")
}

/// An 8×8 PNG: the source the good encodings are said to be made from.
fn source_png() -> Vec<u8> {
    std::fs::read(dir().join("source.png")).unwrap()
}

/// A well-formed 8×8 image in `format` (its blocks are not a real encoding of the PNG: the
/// tests check the container, and decoding any block bytes must work).
fn good(format: BlockFormat, srgb: bool) -> BlockImage {
    let (w, h) = (8, 8);
    let levels = (0..full_chain(w, h))
        .map(|i| {
            let (lw, lh) = level_size(w, h, i);
            (0..format.level_bytes(lw, lh))
                .map(|b| (b * 131 + i * 7) as u8)
                .collect()
        })
        .collect();
    BlockImage {
        format,
        srgb,
        width: w,
        height: h,
        levels,
        source_hash: Some(fnv1a64(&source_png())),
    }
}

/// The corpus: (file, bytes, why it is bad — `None` for a good file).
fn corpus() -> Vec<(&'static str, Vec<u8>, Option<&'static str>)> {
    let bc1 = good(BlockFormat::Bc1, true).write();
    let etc2 = good(BlockFormat::Etc2Rgb8, true).write();
    let mut lying_size = bc1.clone();
    lying_size[20..24].copy_from_slice(&16u32.to_le_bytes()); // width 16: levels too short
    let mut missing_levels = bc1.clone();
    missing_levels[40..44].copy_from_slice(&9u32.to_le_bytes()); // 9 levels: the index runs into the DFD
    let mut empty_level = good(BlockFormat::Bc1, true);
    empty_level.levels[1].clear(); // level 1 (4×4) stored without its block
    let mut basis = bc1.clone();
    basis[12..16].copy_from_slice(&0u32.to_le_bytes()); // VK_FORMAT_UNDEFINED
    basis[44..48].copy_from_slice(&1u32.to_le_bytes()); // BasisLZ
    let mut rgba8 = bc1.clone();
    rgba8[12..16].copy_from_slice(&43u32.to_le_bytes()); // R8G8B8A8_SRGB: not a block format
    let mut garbage = bc1[..12].to_vec();
    garbage.extend((0..200u32).map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8));
    vec![
        ("good-bc1.ktx2", bc1.clone(), None),
        ("good-etc2.ktx2", etc2.clone(), None),
        (
            "truncated.ktx2",
            bc1[..bc1.len() - 40].to_vec(),
            Some("truncated"),
        ),
        ("lying-size.ktx2", lying_size, Some("width 16, levels of 8")),
        (
            "missing-levels.ktx2",
            missing_levels,
            Some("9 levels claimed"),
        ),
        (
            "empty-level.ktx2",
            empty_level.write(),
            Some("level 1 empty"),
        ),
        ("basis.ktx2", basis, Some("Basis Universal")),
        ("rgba8.ktx2", rgba8, Some("uncompressed format")),
        ("garbage.ktx2", garbage, Some("garbage after the magic")),
        // Good files, wrong for the colour role: linear data.
        (
            "linear-bc1.ktx2",
            good(BlockFormat::Bc1, false).write(),
            None,
        ),
        (
            "linear-etc2.ktx2",
            good(BlockFormat::Etc2Rgb8, false).write(),
            None,
        ),
    ]
}

/// The committed files are the corpus (`DERMIS_WRITE_KTX2_CORPUS=1` writes them).
#[test]
fn the_committed_corpus_is_current() {
    let write = std::env::var("DERMIS_WRITE_KTX2_CORPUS").is_ok_and(|v| v == "1");
    for (name, bytes, _) in corpus() {
        let path = dir().join(name);
        if write {
            std::fs::write(&path, &bytes).unwrap();
        }
        let committed = std::fs::read(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(committed == bytes, "{name} differs from the corpus");
    }
}

#[test]
fn bad_files_are_one_line_and_good_ones_read_back() {
    for (name, _, bad) in corpus() {
        let bytes = std::fs::read(dir().join(name)).unwrap();
        match (BlockImage::read(&bytes, LIMITS), bad) {
            (Ok(img), None) => {
                assert_eq!(img.write(), bytes, "{name}");
                for i in 0..img.levels.len() {
                    let (w, h) = level_size(img.width, img.height, i);
                    assert_eq!(img.decode_level(i).unwrap().len(), (w * h * 4) as usize);
                }
            }
            (Err(e), Some(_)) => assert!(!e.is_empty() && !e.contains('\n'), "{name}: {e}"),
            (Ok(_), Some(why)) => panic!("{name} ({why}) was read"),
            (Err(e), None) => panic!("{name}: {e}"),
        }
    }
}

#[test]
fn the_wrong_colour_space_is_refused_for_its_role() {
    let read = |name| BlockImage::read(&std::fs::read(dir().join(name)).unwrap(), LIMITS).unwrap();
    assert!(read("good-bc1.ktx2")
        .check_role(TextureRole::Colour)
        .is_ok());
    let e = read("linear-bc1.ktx2")
        .check_role(TextureRole::Colour)
        .unwrap_err();
    assert!(e.contains("linear") && e.contains("sRGB"), "{e}");
    assert!(read("linear-bc1.ktx2")
        .check_role(TextureRole::Data)
        .is_ok());
    assert!(read("good-etc2.ktx2")
        .check_role(TextureRole::Data)
        .is_err());
}

/// The loader's choice for a PNG source whose encodings are the files named: usable ones are
/// kept, in family order; unusable ones are left out; none usable: the PNG decoded.
fn load(bc: &str, etc2: &str, role: TextureRole) -> dermis_engine::asset::TextureImage {
    let files = [(Family::Bc, bc), (Family::Etc2, etc2)];
    let sidecar = |f: Family| {
        files
            .iter()
            .find(|(g, _)| *g == f)
            .map_or("none".into(), |(_, n)| n.to_string())
    };
    let read = |p: &str| std::fs::read(dir().join(p)).map_err(|e| e.to_string());
    encoded_texture(&source_png(), role, &sidecar, &read, "test image").unwrap()
}

fn formats(t: &dermis_engine::asset::TextureImage) -> Vec<BlockFormat> {
    match &t.texels {
        Texels::Blocks(e) => e.iter().map(|e| e.format).collect(),
        Texels::Rgba8(_) => Vec::new(),
    }
}

#[test]
fn the_loader_keeps_usable_encodings_and_falls_back_to_the_source() {
    let both = load("good-bc1.ktx2", "good-etc2.ktx2", TextureRole::Colour);
    assert_eq!(
        formats(&both),
        [BlockFormat::Bc1, BlockFormat::Etc2Rgb8],
        "both encodings"
    );
    for bad in [
        "truncated.ktx2",
        "lying-size.ktx2",
        "basis.ktx2",
        "garbage.ktx2",
    ] {
        let t = load(bad, "good-etc2.ktx2", TextureRole::Colour);
        assert_eq!(formats(&t), [BlockFormat::Etc2Rgb8], "{bad} left out");
    }
    // Wrong for the role, or made from another image: the PNG, decoded.
    let t = load("linear-bc1.ktx2", "linear-etc2.ktx2", TextureRole::Colour);
    assert!(matches!(&t.texels, Texels::Rgba8(px) if px.len() == 8 * 8 * 4));
    let stale = encoded_texture(
        &std::fs::read(dir().join("other.png")).unwrap(),
        TextureRole::Colour,
        &|_| "good-bc1.ktx2".into(),
        &|p: &str| std::fs::read(dir().join(p)).map_err(|e| e.to_string()),
        "other image",
    )
    .unwrap();
    assert!(
        matches!(stale.texels, Texels::Rgba8(_)),
        "stale encoding used"
    );
    // No source (the APK): the encodings are all there is; none usable is one error.
    let read = |p: &str| std::fs::read(dir().join(p)).map_err(|e| e.to_string());
    let only = encoded_texture(
        &[],
        TextureRole::Colour,
        &|_| "good-etc2.ktx2".into(),
        &read,
        "x",
    )
    .unwrap();
    assert_eq!(formats(&only), [BlockFormat::Etc2Rgb8]);
    let none = encoded_texture(
        &[],
        TextureRole::Colour,
        &|_| "garbage.ktx2".into(),
        &read,
        "x",
    );
    assert!(none.is_err_and(|e| !e.contains('\n')));
    // A KTX2 image (an APK glb's, pointing at its colour encoding) read as data: the data
    // encoding beside it, else one error.
    let etc2 = std::fs::read(dir().join("good-etc2.ktx2")).unwrap();
    let data = encoded_texture(
        &etc2,
        TextureRole::Data,
        &|_| "linear-etc2.ktx2".into(),
        &read,
        "x",
    )
    .unwrap();
    assert_eq!(formats(&data), [BlockFormat::Etc2Rgb8]);
    assert!(!data.srgb);
    let none = encoded_texture(&etc2, TextureRole::Data, &|_| "none".into(), &read, "x");
    assert!(none.is_err_and(|e| !e.contains('\n')));
}
