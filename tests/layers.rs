//! The core's files form layers (docs/ARCHITECTURE.md, "The layers"): no file imports one of a
//! layer above its own, and no two files import each other, directly or around a loop. Both are
//! read off the source: every `use` tree and every inline `crate::`/`super::` path of every file
//! under `src/` (test modules and comments left out), each resolved to the file that declares
//! the module it names. A re-export counts as an import, so a submodule that reads a type through
//! its parent's `pub use` closes a loop with that parent: it imports the file that defines it.
#![cfg(not(target_arch = "wasm32"))]

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The top-level modules from the bottom up; a file may import its own layer's and lower ones'.
/// The base (helpers every layer uses) is layer 0; `lib.rs` sits above everything.
const LAYERS: &[&[&str]] = &[
    &["util", "seed", "error", "dispatch", "reuse", "param"],
    &["arena"],
    &["render"],
    &["encoder"],
    &["env"],
    &["memory"],
    &["agent"],
    &["experiment"],
    &["session"],
    &["web"],
];

/// A source file: its module path (`agent::table`; empty for `lib.rs`) and its text.
struct File {
    module: Vec<String>,
    path: PathBuf,
    text: String,
}

fn read(dir: &Path, module: &[String], out: &mut Vec<File>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for path in entries {
        let name = path.file_stem().unwrap().to_str().unwrap().to_string();
        if path.is_dir() {
            let mut m = module.to_vec();
            m.push(name);
            read(&path, &m, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let mut m = module.to_vec();
            if name != "mod" && name != "lib" {
                m.push(name);
            }
            let text = std::fs::read_to_string(&path).unwrap();
            out.push(File { module: m, path, text });
        }
    }
}

/// The text without comments, string contents and `#[cfg(test)]` modules.
fn code(text: &str) -> String {
    let text = match text.find("#[cfg(test)]\nmod tests") {
        Some(i) => &text[..i],
        None => text,
    };
    let mut out = String::with_capacity(text.len());
    let b = text.as_bytes();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
            i += 2;
            while i + 1 < b.len() && !(b[i] == b'*' && b[i + 1] == b'/') {
                i += 1;
            }
            i += 2;
        } else if b[i] == b'"' && !(i > 0 && b[i - 1] == b'\'') {
            // A string: skip to its end (raw strings hold no quote-hash pairs here).
            let raw = i > 0 && (b[i - 1] == b'r' || b[i - 1] == b'#');
            let hashes = if raw { text[..i].chars().rev().take_while(|c| *c == '#').count() } else { 0 };
            i += 1;
            while i < b.len() {
                if !raw && b[i] == b'\\' {
                    i += 2;
                    continue;
                }
                if b[i] == b'"' && b[i + 1..].iter().take(hashes).all(|c| *c == b'#') {
                    i += 1 + hashes;
                    break;
                }
                i += 1;
            }
            out.push_str("\"\"");
        } else {
            out.push(b[i] as char);
            i += 1;
        }
    }
    inline_modules(&out)
}

/// `code` with `super::` inside an inline module (`mod avx2 { use super::x; }`) written as the
/// `self::` of the file that holds it, which is what it names.
fn inline_modules(code: &str) -> String {
    let mut out = code.to_string();
    let mut from = 0;
    while let Some(i) = out[from..].find("mod ").map(|i| from + i) {
        from = i + 4;
        let after = &out[from..];
        let name_len = after.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(0);
        let rest = after[name_len..].trim_start();
        if name_len == 0 || !rest.starts_with('{') {
            continue;
        }
        let open = from + name_len + (after.len() - name_len - rest.len());
        let mut depth = 0;
        let mut close = out.len();
        for (k, c) in out[open..].char_indices() {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        close = open + k;
                        break;
                    }
                }
                _ => {}
            }
        }
        let body = out[open..close].replace("super::", "self::");
        out.replace_range(open..close, &body);
    }
    out
}

/// The paths a `use` tree names with the names they bind (`a::{b::{C, D as E}, f}` gives
/// `a::b::C` as `C`, `a::b::D` as `E`, `a::f` as `f`; `a::*` binds `*`).
fn expand(tree: &str, prefix: &str, out: &mut Vec<(String, String)>) {
    let tree = tree.trim();
    if let Some(open) = tree.find('{') {
        let head = tree[..open].trim().trim_end_matches("::");
        let inner = &tree[open + 1..tree.rfind('}').unwrap()];
        let base = join(prefix, head);
        let mut depth = 0;
        let mut start = 0;
        for (i, c) in inner.char_indices() {
            match c {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    expand(&inner[start..i], &base, out);
                    start = i + 1;
                }
                _ => {}
            }
        }
        expand(&inner[start..], &base, out);
    } else if !tree.is_empty() {
        let mut parts = tree.split(" as ");
        let path = join(prefix, parts.next().unwrap().trim());
        let bound = match parts.next() {
            Some(alias) => alias.trim().to_string(),
            None if path.ends_with("::self") => {
                path.trim_end_matches("::self").rsplit("::").next().unwrap().to_string()
            }
            None => path.rsplit("::").next().unwrap().to_string(),
        };
        out.push((path.trim_end_matches("::self").to_string(), bound));
    }
}

fn join(a: &str, b: &str) -> String {
    match (a.is_empty(), b.is_empty()) {
        (true, _) => b.to_string(),
        (_, true) => a.to_string(),
        _ => format!("{a}::{b}"),
    }
}

/// What a file names: the paths of its `use` trees (with whether the `use` is public, a
/// re-export, and the name it binds) and its inline `crate::`, `super::` and `self::` paths.
#[derive(Default)]
struct Names {
    uses: Vec<(bool, String, String)>,
    inline: Vec<String>,
}

fn names(code: &str) -> Names {
    let mut out = Names::default();
    let mut rest_code = String::new();
    let mut rest = code;
    while let Some(i) = rest.find("use ") {
        let bytes = rest.as_bytes();
        let word_start = i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_');
        let end = rest[i..].find(';').map(|e| i + e);
        match end {
            Some(end) if word_start => {
                let before = &rest[..i];
                let public = before.trim_end().ends_with("pub") || before.trim_end().ends_with(')');
                let mut trees = Vec::new();
                expand(&rest[i + 4..end], "", &mut trees);
                for (path, alias) in trees {
                    out.uses.push((public, path, alias));
                }
                rest_code.push_str(before);
                rest = &rest[end..];
            }
            _ => {
                rest_code.push_str(&rest[..i + 4]);
                rest = &rest[i + 4..];
            }
        }
    }
    rest_code.push_str(rest);
    let bytes = rest_code.as_bytes();
    for start in ["crate::", "super::", "self::"] {
        for (i, _) in rest_code.match_indices(start) {
            if i > 0 && (bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_' || bytes[i - 1] == b':') {
                continue;
            }
            let len = rest_code[i..]
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == ':'))
                .unwrap_or(rest_code.len() - i);
            out.inline.push(rest_code[i..i + len].trim_end_matches(':').to_string());
        }
    }
    out
}

/// The module a path starts from, and the segments after it: `crate`, `self` and `super` as
/// Rust reads them in `from`, or (the 2018 edition's uniform paths) a child module of `from`.
fn start<'a>(
    path: &'a str,
    from: &File,
    modules: &BTreeMap<Vec<String>, usize>,
) -> Option<(Vec<String>, Vec<&'a str>)> {
    let segs: Vec<&str> = path.split("::").collect();
    let mut base = match segs[0] {
        "crate" => Vec::new(),
        // `self` in `a/mod.rs` is `a`, in `a/b.rs` `a::b`; each `super` is one up from there.
        "super" | "self" => from.module.clone(),
        first => {
            let mut child = from.module.clone();
            child.push(first.to_string());
            if !modules.contains_key(&child) {
                return None; // another crate
            }
            from.module.clone()
        }
    };
    let mut i = 0;
    while i < segs.len() && matches!(segs[i], "super" | "self" | "crate") {
        if segs[i] == "super" {
            base.pop();
        }
        i += 1;
    }
    Some((base, segs[i..].to_vec()))
}

/// The file that defines what `path` names from `from`: the deepest module along the path that
/// has a file, then through that file's re-exports (`pub use`) to the file behind them.
fn resolve(path: &str, from: usize, g: &Sources, depth: usize) -> Option<usize> {
    let (mut module, segs) = start(path, &g.files[from], &g.modules)?;
    let mut file = *g.modules.get(&module)?;
    let mut k = 0;
    while k < segs.len() {
        module.push(segs[k].to_string());
        match g.modules.get(&module) {
            Some(f) => file = *f,
            None => break,
        }
        k += 1;
    }
    let Some(item) = segs.get(k) else { return Some(file) };
    if depth < 8 {
        let exported = g.names[file].uses.iter().find(|(public, _, alias)| *public && alias == item);
        if let Some((_, target, _)) = exported {
            let rest: Vec<&str> = segs[k + 1..].to_vec();
            let full = if rest.is_empty() { target.clone() } else { format!("{target}::{}", rest.join("::")) };
            return resolve(&full, file, g, depth + 1);
        }
        // A glob re-export: the file it reads from, if that file defines the item.
        for (public, target, alias) in &g.names[file].uses {
            if *public && alias == "*" {
                if let Some(t) = resolve(target, file, g, depth + 1) {
                    if defines(&g.files[t].text, item) {
                        return Some(t);
                    }
                }
            }
        }
    }
    Some(file)
}

/// Whether `text` declares a public item called `name`.
fn defines(text: &str, name: &str) -> bool {
    ["const", "static", "fn", "struct", "enum", "type", "trait", "mod"].iter().any(|kind| {
        text.match_indices(&format!("pub {kind} {name}"))
            .any(|(i, m)| text[i + m.len()..].chars().next().is_none_or(|c| !(c.is_alphanumeric() || c == '_')))
    })
}

fn layer(module: &[String]) -> Option<usize> {
    let top = module.first()?;
    LAYERS.iter().position(|l| l.contains(&top.as_str()))
}

/// The source files, what each names, and the files each imports.
struct Sources {
    files: Vec<File>,
    modules: BTreeMap<Vec<String>, usize>,
    names: Vec<Names>,
    edges: Vec<BTreeSet<usize>>,
}

fn graph() -> Sources {
    let mut files = Vec::new();
    read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src"), &[], &mut files);
    let modules = files.iter().enumerate().map(|(i, f)| (f.module.clone(), i)).collect();
    let names = files.iter().map(|f| names(&code(&f.text))).collect();
    let mut g = Sources { files, modules, names, edges: Vec::new() };
    // A re-export forwards a name (it is followed when a path goes through it); the other
    // imports and the inline paths are what a file uses.
    g.edges = (0..g.files.len())
        .map(|i| {
            let n = &g.names[i];
            let used = n.uses.iter().filter(|u| !u.0).map(|u| &u.1).chain(&n.inline);
            used.filter_map(|p| resolve(p, i, &g, 0)).filter(|&j| j != i).collect()
        })
        .collect();
    g
}

fn name(f: &File) -> String {
    f.path.strip_prefix(env!("CARGO_MANIFEST_DIR")).unwrap().display().to_string()
}

#[test]
fn no_file_imports_a_layer_above_its_own() {
    let g = graph();
    let mut up = Vec::new();
    for (i, targets) in g.edges.iter().enumerate() {
        for &j in targets {
            let (a, b) = (&g.files[i], &g.files[j]);
            match (layer(&a.module), layer(&b.module)) {
                (Some(la), Some(lb)) if lb > la => up.push(format!("{} -> {}", name(a), name(b))),
                (Some(_), None) => up.push(format!("{} -> {} (the crate root re-exports)", name(a), name(b))),
                _ => {}
            }
        }
    }
    assert!(up.is_empty(), "imports up the layers (docs/ARCHITECTURE.md):\n{}", up.join("\n"));
}

#[test]
fn no_two_files_import_each_other_around_a_loop() {
    let g = graph();
    // Tarjan's strongly connected components; any with two files or more is a loop.
    struct T<'a> {
        g: &'a Sources,
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        loops: Vec<Vec<usize>>,
    }
    fn visit(t: &mut T, v: usize) {
        t.index[v] = Some(t.next);
        t.low[v] = t.next;
        t.next += 1;
        t.stack.push(v);
        t.on[v] = true;
        for &w in &t.g.edges[v] {
            match t.index[w] {
                None => {
                    visit(t, w);
                    t.low[v] = t.low[v].min(t.low[w]);
                }
                Some(iw) if t.on[w] => t.low[v] = t.low[v].min(iw),
                _ => {}
            }
        }
        if Some(t.low[v]) == t.index[v] {
            let mut scc = Vec::new();
            loop {
                let w = t.stack.pop().unwrap();
                t.on[w] = false;
                scc.push(w);
                if w == v {
                    break;
                }
            }
            if scc.len() > 1 {
                t.loops.push(scc);
            }
        }
    }
    let n = g.files.len();
    let mut t = T {
        g: &g,
        index: vec![None; n],
        low: vec![0; n],
        on: vec![false; n],
        stack: Vec::new(),
        next: 0,
        loops: Vec::new(),
    };
    for v in 0..n {
        if t.index[v].is_none() {
            visit(&mut t, v);
        }
    }
    let shown: Vec<String> = t
        .loops
        .iter()
        .map(|scc| {
            let inside: BTreeSet<usize> = scc.iter().copied().collect();
            let edges: Vec<String> = scc
                .iter()
                .flat_map(|&a| g.edges[a].iter().filter(|b| inside.contains(b)).map(move |&b| (a, b)))
                .map(|(a, b)| format!("  {} -> {}", name(&g.files[a]), name(&g.files[b])))
                .collect();
            edges.join("\n")
        })
        .collect();
    assert!(shown.is_empty(), "files that import each other around a loop:\n{}", shown.join("\n\n"));
}

#[test]
fn the_reader_finds_imports_of_every_form() {
    let mut v = Vec::new();
    expand("crate::a::{b::{C, D as E}, f::{self}}", "", &mut v);
    let v: Vec<(&str, &str)> = v.iter().map(|(p, a)| (p.as_str(), a.as_str())).collect();
    assert_eq!(v, [("crate::a::b::C", "C"), ("crate::a::b::D", "E"), ("crate::a::f", "f")]);
    let c = code("pub use super::x; // crate::y\nlet s = \"crate::z\"; crate::w::f();\n#[cfg(test)]\nmod tests { use crate::q; }");
    let n = names(&c);
    assert_eq!(n.uses, [(true, "super::x".to_string(), "x".to_string())]);
    assert_eq!(n.inline, ["crate::w::f"]);
    assert_eq!(names(&code("mod a {\n use super::b;\n}\nuse super::c;")).uses.len(), 2);
    assert!(code("mod a { use super::b; }").contains("self::b"));
    assert!(defines("pub struct Ab;\npub fn a()", "a") && !defines("pub struct Ab;", "A"));
}
