//! `cargo xtask` builds xtask alone, so cargo resolves its dependencies' features for xtask
//! only; where they differ from the workspace test build's, every crate above them (wgpu,
//! naga, the engine: 33 crates) is compiled a second time. xtask's manifest names the
//! features the rest of the workspace turns on; this test checks the list is still enough.

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;
    use std::process::Command;

    /// Every package of xtask's build with its features, as `cargo tree` prints them.
    fn tree(args: &[&str]) -> BTreeSet<String> {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
        let out = Command::new(env!("CARGO"))
            .current_dir(root)
            .args(["tree", "--locked", "--offline", "--prefix", "none"])
            .args(["--format", "{p} [{f}]"])
            .args(args)
            .output()
            .expect("cargo runs");
        assert!(
            out.status.success(),
            "cargo tree {args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .map(|l| l.trim_end_matches(" (*)").to_string())
            .collect()
    }

    /// Each crate `cargo xtask` builds has the features the workspace's test build (the
    /// README's `cargo test --workspace`, no optional feature) gives it, so the xtask run after
    /// it compiles nothing but xtask.
    #[test]
    fn xtask_features_match_the_workspace() {
        let xtask = tree(&["-p", "xtask", "-e", "normal,build"]);
        let workspace = tree(&["--workspace", "-e", "normal,build,dev"]);
        assert!(xtask.len() > 50, "{} packages", xtask.len());
        let differ: Vec<&String> = xtask.difference(&workspace).collect();
        assert!(
            differ.is_empty(),
            "built by `cargo xtask` with other features than the workspace's test build \
             (name the workspace's in xtask/Cargo.toml): {differ:?}"
        );
    }
}
