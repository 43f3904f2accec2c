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
//!
//! The scan of the modules is here; the tests are in `inside_crates` and `between_crates`.

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

mod between_crates;
mod inside_crates;
