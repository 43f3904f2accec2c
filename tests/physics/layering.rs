//! The layering holds: no module of a crate imports a module that imports it back, and
//! the physics crate depends on no command line, C types or trainer.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use stickslip_tests::workspace_root;

/// Module name (`neural::law`, `crate` for lib.rs/main.rs) -> its source without comment
/// lines and without the `#[cfg(test)] mod tests` block.
fn modules(src: &Path) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            if path.extension().and_then(|e| e.to_str()) != Some("rs") {
                continue;
            }
            let relative = path.strip_prefix(src).unwrap().with_extension("");
            let mut name = relative.to_string_lossy().replace('/', "::");
            if let Some(parent) = name.strip_suffix("::mod") {
                name = parent.to_string();
            }
            if name == "lib" || name == "main" {
                name = "crate".into();
            }
            let text = std::fs::read_to_string(&path).unwrap();
            let text = text.split("#[cfg(test)]\nmod tests").next().unwrap_or("");
            let code: Vec<&str> = text
                .lines()
                .filter(|l| !l.trim_start().starts_with("//"))
                .collect();
            out.insert(name, code.join("\n"));
        }
    }
    out
}

/// The modules each module names through `crate::` (or `super::` from a submodule).
fn imports(modules: &BTreeMap<String, String>) -> BTreeMap<String, BTreeSet<String>> {
    let word = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_lowercase() || *c == '_' || c.is_ascii_digit())
            .collect()
    };
    let mut graph = BTreeMap::new();
    for (name, code) in modules {
        let mut targets = BTreeSet::new();
        for piece in code.split("crate::").skip(1) {
            let first = word(piece);
            let rest = piece[first.len()..].strip_prefix("::").map(word);
            let nested = rest.map(|r| format!("{first}::{r}"));
            let target = match nested {
                Some(n) if modules.contains_key(&n) => n,
                _ => first,
            };
            if modules.contains_key(&target) && &target != name {
                targets.insert(target);
            }
        }
        if let Some((parent, _)) = name.rsplit_once("::") {
            for piece in code.split("super::").skip(1) {
                let target = format!("{parent}::{}", word(piece));
                if modules.contains_key(&target) && &target != name {
                    targets.insert(target);
                }
            }
        }
        graph.insert(name.clone(), targets);
    }
    graph
}

/// A module that reaches itself through its imports, with the path, if any.
fn cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    for start in graph.keys().filter(|m| *m != "crate") {
        let mut stack = vec![vec![start.clone()]];
        let mut seen = BTreeSet::new();
        while let Some(path) = stack.pop() {
            let last = path.last().unwrap();
            for next in &graph[last] {
                if next == start {
                    let mut found = path.clone();
                    found.push(next.clone());
                    return Some(found);
                }
                if next != "crate" && seen.insert(next.clone()) {
                    let mut longer = path.clone();
                    longer.push(next.clone());
                    stack.push(longer);
                }
            }
        }
    }
    None
}

#[test]
fn no_module_imports_one_that_imports_it_back() {
    for krate in ["physics", "train", "fmi", "cli"] {
        let modules = modules(&workspace_root().join("src").join(krate).join("src"));
        assert!(
            modules.len() > 3,
            "{krate}: {} modules found",
            modules.len()
        );
        let graph = imports(&modules);
        assert!(
            graph.values().map(BTreeSet::len).sum::<usize>() > 0,
            "{krate}: no imports found; the scan is broken"
        );
        if let Some(path) = cycle(&graph) {
            panic!("{krate}: import cycle {}", path.join(" -> "));
        }
    }
}

#[test]
fn the_cycle_finder_finds_a_cycle() {
    let mut modules = BTreeMap::new();
    modules.insert("a".to_string(), "use crate::b::X;".to_string());
    modules.insert("b".to_string(), "fn f() { crate::c::g() }".to_string());
    modules.insert("c".to_string(), "use crate::a;".to_string());
    modules.insert("d".to_string(), "// use crate::a;".to_string());
    let graph = imports(&modules);
    assert_eq!(cycle(&graph).map(|p| p.len()), Some(4));
    modules.insert("c".to_string(), String::new());
    assert_eq!(cycle(&imports(&modules)), None);
}

/// The physics crate is plain Rust: no clap, no C types, no trainer, no FMI.
#[test]
fn the_physics_crate_depends_on_no_outer_layer() {
    let manifest =
        std::fs::read_to_string(workspace_root().join("src/physics/Cargo.toml")).unwrap();
    let manifest: toml::Table = manifest.parse().unwrap();
    let dependencies = manifest["dependencies"].as_table().unwrap();
    for outer in [
        "clap",
        "libc",
        "stickslip-train",
        "stickslip-fmi",
        "stickslip-cli",
        "rand",
    ] {
        assert!(
            !dependencies.contains_key(outer),
            "src/physics depends on {outer}"
        );
    }
}
