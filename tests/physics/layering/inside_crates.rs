//! Inside each crate: no module imports one that imports it back; the scan and the cycle
//! finder checked on planted modules.

use super::*;

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
