//! Between the crates: the manifests point one way.

use super::*;

/// The `[dependencies]` (and build- and target-specific dependencies) of a member's
/// manifest, by package name (a renamed dependency counts as the package it renames).
fn dependencies(member: &str) -> BTreeSet<String> {
    let manifest =
        std::fs::read_to_string(workspace_root().join(member).join("Cargo.toml")).unwrap();
    let manifest: toml::Table = manifest.parse().unwrap();
    let mut tables = Vec::new();
    for key in ["dependencies", "build-dependencies"] {
        tables.extend(manifest.get(key).and_then(|t| t.as_table()));
        if let Some(targets) = manifest.get("target").and_then(|t| t.as_table()) {
            for target in targets.values() {
                tables.extend(target.get(key).and_then(|t| t.as_table()));
            }
        }
    }
    let mut names = BTreeSet::new();
    for table in tables {
        for (key, value) in table {
            let package = value.get("package").and_then(|p| p.as_str()).unwrap_or(key);
            names.insert(package.to_string());
        }
    }
    names
}

/// The arrows between the crates point one way: the physics is plain Rust (no clap, no C
/// types, no trainer, no FMI, no command line); the trainer and the FMI adapter sit side by
/// side over it; the command line uses the physics and the trainer, not the FMI adapter.
#[test]
fn the_manifests_point_one_way() {
    let forbidden: [(&str, &[&str]); 4] = [
        (
            "src/physics",
            &[
                "clap",
                "libc",
                "rand",
                "stickslip-train",
                "stickslip-fmi",
                "stickslip-cli",
            ],
        ),
        ("src/train", &["clap", "stickslip-fmi", "stickslip-cli"]),
        ("src/fmi", &["clap", "stickslip-train", "stickslip-cli"]),
        ("src/cli", &["stickslip-fmi"]),
    ];
    for (member, outer) in forbidden {
        let dependencies = dependencies(member);
        assert!(
            dependencies.contains("serde"),
            "{member}: the manifest scan is broken: {dependencies:?}"
        );
        for name in outer {
            assert!(!dependencies.contains(*name), "{member} depends on {name}");
        }
        if member != "src/physics" {
            assert!(
                dependencies.contains("stickslip"),
                "{member}: {dependencies:?}"
            );
        }
    }
}
