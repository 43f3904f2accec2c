//! The layering holds, inside each crate and between the crates.
//!
//! Inside a crate (physics, train, fmi, cli), counting the crate root (lib.rs) as a
//! module like any other:
//! - no module imports a module that imports it back;
//! - no module imports an item through a re-export (`pub use`) of its own crate root or
//!   parent module: those re-exports are for users outside, and a module that names an
//!   item through them depends on every module the root or parent uses.
//!
//! A module imports the module a path names: the deepest module on `crate::a::b::Item`,
//! `super::Item`, `self::a::Item` or `a::Item` (from the parent of `a`), with `{...}`
//! groups expanded. An item reached through a module that only re-exports it counts as
//! an import of that module, since the path depends on the re-export.
//!
//! Between the crates the manifests point one way: the physics depends on no outer
//! layer, the trainer and the FMI adapter not on each other nor on the command line,
//! and the command line not on the FMI adapter.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use stickslip_tests::workspace_root;

/// The source with comments removed and string and character literals emptied, so that
/// only code is scanned for paths.
fn code_only(source: &str) -> String {
    let s: Vec<char> = source.chars().collect();
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    let mut out = String::with_capacity(source.len());
    let mut i = 0;
    while i < s.len() {
        let c = s[i];
        let next = s.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < s.len() && s[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < s.len() {
                if s[i] == '/' && s.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if s[i] == '*' && s.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            out.push(' ');
        } else if c == 'r'
            && (i == 0 || !ident(s[i - 1]) || (s[i - 1] == 'b' && (i < 2 || !ident(s[i - 2]))))
            && matches!(next, Some('"') | Some('#'))
            && s[i + 1..].iter().find(|&&c| c != '#') == Some(&'"')
        {
            // A raw string: r"..." or r#"..."#.
            let hashes = s[i + 1..].iter().take_while(|&&c| c == '#').count();
            i += 2 + hashes;
            while i < s.len() {
                if s[i] == '"' && s[i + 1..].iter().take_while(|&&c| c == '#').count() >= hashes {
                    i += 1 + hashes;
                    break;
                }
                i += 1;
            }
            out.push_str("\"\"");
        } else if c == '"' {
            i += 1;
            while i < s.len() && s[i] != '"' {
                i += if s[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push_str("\"\"");
        } else if c == '\'' && next == Some('\\') {
            // An escaped character: past the quote, the backslash and the escaped
            // character (which may itself be a quote), to the closing quote.
            i += 3;
            while i < s.len() && s[i] != '\'' {
                i += 1;
            }
            i += 1;
            out.push_str("' '");
        } else if c == '\'' && s.get(i + 2) == Some(&'\'') {
            i += 3;
            out.push_str("' '");
        } else {
            // Code, or the quote of a lifetime.
            out.push(c);
            i += 1;
        }
    }
    out
}

/// Module name (`neural::law`, `crate` for lib.rs) -> its code (`code_only`) without the
/// `#[cfg(test)] mod tests` block. A main.rs next to a lib.rs is a binary crate of its
/// own, which uses the library by name; it is left out.
fn modules(src: &Path) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    let has_lib = src.join("lib.rs").is_file();
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
            match name.as_str() {
                "main" if has_lib => continue,
                "lib" | "main" => name = "crate".into(),
                _ => {}
            }
            let code = code_only(&std::fs::read_to_string(&path).unwrap());
            out.insert(name, without_tests(&code).to_string());
        }
    }
    out
}

/// The code before `#[cfg(test)] mod tests`.
fn without_tests(code: &str) -> &str {
    let mut from = 0;
    while let Some(at) = code[from..].find("#[cfg(test)]") {
        let at = from + at;
        let after = code[at + "#[cfg(test)]".len()..].trim_start();
        if after.starts_with("mod tests") {
            return &code[..at];
        }
        from = at + 1;
    }
    code
}

/// One path of a `use` tree or an expression: its segments, and the name it is bound to
/// if renamed (`as`).
#[derive(Debug, Clone, PartialEq)]
struct PathUse {
    segments: Vec<String>,
    alias: Option<String>,
}

/// Reads the paths of a path or `use` tree starting at `s[*i]`: `a::b::C`,
/// `a::{b, c::{D, E as F}, self}`, `a::*` (the glob ends the path at `a`).
fn tree(s: &[char], i: &mut usize, prefix: &[String], out: &mut Vec<PathUse>) {
    let skip_ws = |i: &mut usize| {
        while *i < s.len() && s[*i].is_whitespace() {
            *i += 1;
        }
    };
    let ident = |i: &mut usize| -> Option<String> {
        let start = *i;
        if *i < s.len() && (s[*i].is_alphabetic() || s[*i] == '_') {
            while *i < s.len() && (s[*i].is_alphanumeric() || s[*i] == '_') {
                *i += 1;
            }
            Some(s[start..*i].iter().collect())
        } else {
            None
        }
    };
    skip_ws(i);
    match s.get(*i) {
        Some('{') => {
            *i += 1;
            loop {
                skip_ws(i);
                match s.get(*i) {
                    Some('}') => {
                        *i += 1;
                        return;
                    }
                    Some(',') => *i += 1,
                    Some(c) if c.is_alphabetic() || *c == '_' || *c == '{' || *c == '*' => {
                        tree(s, i, prefix, out)
                    }
                    _ => return,
                }
            }
        }
        Some('*') => {
            *i += 1;
            out.push(PathUse {
                segments: prefix.to_vec(),
                alias: None,
            });
        }
        _ => {
            let Some(segment) = ident(i) else {
                return;
            };
            let mut path = prefix.to_vec();
            path.push(segment);
            let mut j = *i;
            skip_ws(&mut j);
            if s.get(j) == Some(&':') && s.get(j + 1) == Some(&':') {
                let mut k = j + 2;
                skip_ws(&mut k);
                if matches!(s.get(k), Some(c) if c.is_alphabetic() || *c == '_' || *c == '{' || *c == '*')
                {
                    *i = k;
                    tree(s, i, &path, out);
                    return;
                }
            }
            // A leaf, perhaps renamed.
            let mut alias = None;
            let mut k = *i;
            skip_ws(&mut k);
            if s[k..].starts_with(&['a', 's']) && !s.get(k + 2).is_some_and(|c| c.is_alphanumeric())
            {
                let mut m = k + 2;
                skip_ws(&mut m);
                if let Some(name) = ident(&mut m) {
                    alias = Some(name);
                    *i = m;
                }
            }
            out.push(PathUse {
                segments: path,
                alias,
            });
        }
    }
}

/// The segments of a module name (`crate` has none).
fn segments(module: &str) -> Vec<String> {
    if module == "crate" {
        Vec::new()
    } else {
        module.split("::").map(String::from).collect()
    }
}

fn module_name(segments: &[String]) -> String {
    if segments.is_empty() {
        "crate".into()
    } else {
        segments.join("::")
    }
}

/// The module a path in `from` names (the deepest module on it) and the item after it,
/// if any; None for a path that leaves the crate (`stickslip::scene::Scene`) or starts
/// at a type (`FidelityLevel::Auto`).
fn resolve(
    modules: &BTreeMap<String, String>,
    from: &str,
    path: &[String],
) -> Option<(String, Option<String>)> {
    let mut base = segments(from);
    let mut rest = path.iter().peekable();
    match rest.peek()?.as_str() {
        "crate" => {
            base.clear();
            rest.next();
        }
        "super" => {
            while rest.peek().map(|s| s.as_str()) == Some("super") {
                base.pop()?;
                rest.next();
            }
        }
        "self" => {
            rest.next();
        }
        child => {
            let mut with = base.clone();
            with.push(child.to_string());
            if !modules.contains_key(&module_name(&with)) {
                return None;
            }
        }
    }
    for segment in rest {
        if segment == "self" {
            continue;
        }
        let mut deeper = base.clone();
        deeper.push(segment.clone());
        if modules.contains_key(&module_name(&deeper)) {
            base = deeper;
        } else {
            return Some((module_name(&base), Some(segment.clone())));
        }
    }
    Some((module_name(&base), None))
}

/// Every path in `code` that starts at `crate`, `$crate`, `super`, `self` or a child
/// module of `module`.
fn paths(modules: &BTreeMap<String, String>, module: &str, code: &str) -> Vec<PathUse> {
    let s: Vec<char> = code.chars().collect();
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    let children: BTreeSet<String> = modules
        .keys()
        .filter_map(|m| {
            let mut segs = segments(m);
            let last = segs.pop()?;
            (module_name(&segs) == module).then_some(last)
        })
        .collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < s.len() {
        if !(s[i].is_alphabetic() || s[i] == '_') || (i > 0 && ident(s[i - 1])) {
            i += 1;
            continue;
        }
        let start = i;
        while i < s.len() && ident(s[i]) {
            i += 1;
        }
        let word: String = s[start..i].iter().collect();
        let before = s[..start].iter().rev().find(|c| !c.is_whitespace());
        let after_path_separator = before == Some(&':');
        let starts_a_path =
            matches!(word.as_str(), "crate" | "super" | "self") || children.contains(&word);
        let followed_by_separator = s.get(i) == Some(&':') && s.get(i + 1) == Some(&':');
        if after_path_separator || !starts_a_path || !followed_by_separator {
            continue;
        }
        let mut j = start;
        tree(&s, &mut j, &[], &mut out);
        i = j.max(i);
    }
    out
}

/// The names `module` re-exports with `pub use` (or `pub(crate) use`).
fn re_exports(code: &str) -> BTreeSet<String> {
    let s: Vec<char> = code.chars().collect();
    let mut names = BTreeSet::new();
    for keyword in ["pub use ", "pub(crate) use "] {
        let mut from = 0;
        while let Some(at) = code[from..].find(keyword) {
            let byte = from + at + keyword.len();
            let mut i = code[..byte].chars().count();
            let mut uses = Vec::new();
            tree(&s, &mut i, &[], &mut uses);
            for u in uses {
                if let Some(name) = u.alias.or_else(|| u.segments.last().cloned()) {
                    names.insert(name);
                }
            }
            from = byte;
        }
    }
    names
}

/// What one crate's modules import.
struct Imports {
    /// Module -> the modules it imports.
    graph: BTreeMap<String, BTreeSet<String>>,
    /// (module, imported module) -> the items it names there.
    items: BTreeMap<(String, String), BTreeSet<String>>,
    /// (module, item, ancestor): an item named through a re-export of an ancestor.
    through_re_exports: Vec<(String, String, String)>,
}

fn imports(modules: &BTreeMap<String, String>) -> Imports {
    let re_exported: BTreeMap<&String, BTreeSet<String>> = modules
        .iter()
        .map(|(name, code)| (name, re_exports(code)))
        .collect();
    let mut graph = BTreeMap::new();
    let mut items = BTreeMap::<_, BTreeSet<String>>::new();
    let mut through_re_exports = Vec::new();
    for (name, code) in modules {
        let mut targets = BTreeSet::new();
        for path in paths(modules, name, code) {
            let Some((target, item)) = resolve(modules, name, &path.segments) else {
                continue;
            };
            if &target == name {
                continue;
            }
            let named = items.entry((name.clone(), target.clone())).or_default();
            if let Some(item) = item {
                let ancestor = target == "crate" || name.starts_with(&format!("{target}::"));
                if ancestor
                    && re_exported[&target].contains(&item)
                    && !through_re_exports.contains(&(name.clone(), item.clone(), target.clone()))
                {
                    through_re_exports.push((name.clone(), item.clone(), target.clone()));
                }
                named.insert(item);
            }
            targets.insert(target);
        }
        graph.insert(name.clone(), targets);
    }
    Imports {
        graph,
        items,
        through_re_exports,
    }
}

/// The import cycles: for each module on one, the shortest path from it back to itself,
/// each cycle once.
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    let mut found: Vec<Vec<String>> = Vec::new();
    for start in graph.keys() {
        // Breadth first, so that the path found is a shortest one.
        let mut queue = std::collections::VecDeque::from([vec![start.clone()]]);
        let mut seen = BTreeSet::new();
        'search: while let Some(path) = queue.pop_front() {
            for next in &graph[path.last().unwrap()] {
                if next == start {
                    let mut cycle = path.clone();
                    cycle.push(next.clone());
                    let nodes: BTreeSet<&String> = cycle.iter().collect();
                    if !found
                        .iter()
                        .any(|c| c.iter().collect::<BTreeSet<_>>() == nodes)
                    {
                        found.push(cycle);
                    }
                    break 'search;
                }
                if seen.insert(next.clone()) {
                    let mut longer = path.clone();
                    longer.push(next.clone());
                    queue.push_back(longer);
                }
            }
        }
    }
    found
}

/// What is wrong with one crate's imports, one line each.
fn findings(krate: &str, modules: &BTreeMap<String, String>) -> Vec<String> {
    let found = imports(modules);
    let mut out = Vec::new();
    for cycle in cycles(&found.graph) {
        let mut line = format!("{krate}: import cycle {}", cycle[0]);
        for pair in cycle.windows(2) {
            let named = &found.items[&(pair[0].clone(), pair[1].clone())];
            line += &format!(" -> {}", pair[1]);
            if !named.is_empty() {
                line += &format!(
                    " (for {})",
                    named.iter().cloned().collect::<Vec<_>>().join(", ")
                );
            }
        }
        out.push(line);
    }
    for (module, item, ancestor) in &found.through_re_exports {
        out.push(format!(
            "{krate}: {module} imports {item} through the `pub use` of {ancestor}; import it from the module that defines it"
        ));
    }
    out
}

#[test]
fn no_module_imports_one_that_imports_it_back() {
    let mut all = Vec::new();
    for krate in ["physics", "train", "fmi", "cli"] {
        let modules = modules(&workspace_root().join("src").join(krate).join("src"));
        assert!(
            modules.len() > 3 && modules.contains_key("crate"),
            "{krate}: {} modules found",
            modules.len()
        );
        let graph = imports(&modules).graph;
        assert!(
            graph.values().map(BTreeSet::len).sum::<usize>() >= modules.len() / 2,
            "{krate}: too few imports found; the scan is broken: {graph:?}"
        );
        all.extend(findings(krate, &modules));
    }
    assert!(
        all.is_empty(),
        "the layering inside a crate is broken (each edge names the items it imports):\n{}\n",
        all.join("\n")
    );
}

fn planted(files: &[(&str, &str)]) -> BTreeMap<String, String> {
    files
        .iter()
        .map(|(name, code)| {
            (
                name.to_string(),
                without_tests(&code_only(code)).to_string(),
            )
        })
        .collect()
}

#[test]
fn the_scan_reads_groups_super_self_child_paths_and_renames() {
    let modules = planted(&[
        ("crate", "pub mod a; pub mod n; pub struct Root; fn f() { a::g() }"),
        ("a", "use crate::{Root, n::{self, m::X as Y}, a};"),
        ("n", "pub use m::X; fn h() -> self::m::Z { todo!() }"),
        ("n::m", "use super::super::a::g; use super::*; pub struct X;"),
        ("b", "use stickslip::scene::Scene; fn f() -> Vec::<u8> { FidelityLevel::Auto; \"crate::a\" }"),
        (
            "c",
            r##"fn f<'a>(x: &'a str) { let q = '\''; let r = '"'; let s = r#"crate::a"#;
                let t = "crate::n \" crate::a"; crate::n::m::X::new(x) }
                /* crate::a /* nested */ crate::a */ const C: char = '\u{41}';"##,
        ),
    ]);
    let graph = imports(&modules).graph;
    let targets = |m: &str| graph[m].iter().cloned().collect::<Vec<_>>();
    assert_eq!(targets("crate"), ["a"]);
    assert_eq!(targets("a"), ["crate", "n", "n::m"]);
    assert_eq!(targets("n"), ["n::m"]);
    assert_eq!(targets("n::m"), ["a", "n"]);
    assert!(targets("b").is_empty(), "{:?}", targets("b"));
    // Past lifetimes, character literals, raw and escaped strings and nested comments.
    assert_eq!(targets("c"), ["n::m"]);
    assert_eq!(re_exports(&modules["n"]), BTreeSet::from(["X".to_string()]));
    let mut uses = Vec::new();
    let code: Vec<char> = "a::{b, c::{D, E as F}, self}".chars().collect();
    tree(&code, &mut 0, &[], &mut uses);
    let leaves: Vec<String> = uses
        .iter()
        .map(|u| {
            u.segments.join("::")
                + &u.alias
                    .as_ref()
                    .map_or(String::new(), |a| format!(" as {a}"))
        })
        .collect();
    assert_eq!(leaves, ["a::b", "a::c::D", "a::c::E as F", "a::self"]);
}

#[test]
fn the_cycle_finder_finds_a_cycle() {
    let mut modules = planted(&[
        ("crate", "pub mod a; pub mod b; pub mod c; pub mod d;"),
        ("a", "use crate::b::X;"),
        ("b", "fn f() { crate::c::g() }"),
        ("c", "use crate::a;"),
        (
            "d",
            "// use crate::a;\n/* crate::b */ fn f() { \"crate::c\" }",
        ),
    ]);
    assert_eq!(cycles(&imports(&modules).graph), [["a", "b", "c", "a"]]);
    assert!(imports(&modules).graph["d"].is_empty());
    modules.insert("c".to_string(), String::new());
    assert!(cycles(&imports(&modules).graph).is_empty());

    // Through the crate root: it uses a module that imports an item defined in lib.rs.
    let root = planted(&[
        (
            "crate",
            "pub mod beam; pub trait Model {} fn info() { beam::Beam::INFO }",
        ),
        ("beam", "use crate::{Model, other}; pub struct Beam;"),
        ("other", ""),
    ]);
    assert_eq!(
        findings("planted", &root),
        ["planted: import cycle beam -> crate (for Model) -> beam (for Beam)"]
    );

    // Through a parent's re-export: `super::Error` where mod.rs only re-exports it.
    let parent = planted(&[
        ("crate", "pub mod neural;"),
        (
            "neural",
            "mod error; pub mod law; pub use error::Error; fn f() { law::Law::new() }",
        ),
        ("neural::error", "pub struct Error;"),
        ("neural::law", "use super::Error; pub struct Law;"),
    ]);
    assert_eq!(cycles(&imports(&parent).graph).len(), 1);
    let found = findings("planted", &parent);
    assert!(
        found
            .iter()
            .any(|f| f.contains("neural::law imports Error through the `pub use` of neural")),
        "{found:?}"
    );
    let fixed = planted(&[
        ("crate", "pub mod neural;"),
        (
            "neural",
            "mod error; pub mod law; pub use error::Error; fn f() { law::Law::new() }",
        ),
        ("neural::error", "pub struct Error;"),
        ("neural::law", "use super::error::Error; pub struct Law;"),
    ]);
    assert_eq!(findings("planted", &fixed), Vec::<String>::new());

    // A root that only re-exports: no cycle, but still named through the re-export.
    let re_export = planted(&[
        ("crate", "mod error; pub mod run; pub use error::Error;"),
        ("error", "pub enum Error {}"),
        ("run", "use crate::Error;"),
    ]);
    assert!(cycles(&imports(&re_export).graph).is_empty());
    assert_eq!(findings("planted", &re_export).len(), 1);
}

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
