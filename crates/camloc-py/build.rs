//! The Python objects' docstrings come from the stub `camloc.pyi`, the one text IDEs read:
//! each documented object's docstring is written to `OUT_DIR/doc/NAME.txt` (`module`,
//! `reconstruct`, `Localizer`, `Localizer.localize`, ...), which the sources include as their
//! doc attributes, so that `help()` and `?` in a notebook show what the stub says.

use std::path::Path;

fn main() {
    let manifest = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let stub = Path::new(&manifest).join("camloc.pyi");
    println!("cargo:rerun-if-changed={}", stub.display());
    let text = std::fs::read_to_string(&stub).expect("camloc.pyi beside Cargo.toml");
    let out = Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("doc");
    // Only this stub's docstrings (none left from an earlier version of it).
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).expect("OUT_DIR is writable");
    for (name, doc) in docstrings(&text) {
        std::fs::write(out.join(format!("{name}.txt")), doc).expect("OUT_DIR is writable");
    }
}

/// The docstrings of the stub, by qualified name: the module's (`module`), each class's
/// (followed by its `__init__`'s), each function's and each method's (`Class.method`).
fn docstrings(text: &str) -> Vec<(String, String)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    if let Some(doc) = docstring_at(&lines, 0) {
        out.push(("module".to_owned(), doc));
    }
    let mut class: Option<String> = None;
    for (i, line) in lines.iter().enumerate() {
        let code = line.trim_start();
        let nested = code.len() < line.len();
        if !nested && !code.is_empty() && !code.starts_with(['"', ')', '@']) {
            class = None;
        }
        if let Some(rest) = code.strip_prefix("class ").filter(|_| !nested) {
            let name = rest
                .split(['(', ':'])
                .next()
                .unwrap_or(rest)
                .trim()
                .to_owned();
            if let Some(doc) = docstring_at(&lines, i + 1) {
                out.push((name.clone(), doc));
            }
            class = Some(name);
        } else if let Some(rest) = code.strip_prefix("def ") {
            let name = rest.split('(').next().unwrap_or(rest).trim();
            // The signature ends at the first line ending in `:` (its return annotation), or
            // in `...` (a stub's body on its line, without a docstring).
            let ends = |j: usize| {
                let line = lines[j].trim_end();
                line.ends_with(':') || line.ends_with("...")
            };
            let Some(end) = (i..lines.len()).find(|&j| ends(j)) else {
                continue;
            };
            let Some(doc) = docstring_at(&lines, end + 1) else {
                continue;
            };
            match (&class, nested) {
                (Some(class), true) if name == "__init__" => {
                    if let Some((_, own)) = out.iter_mut().find(|(n, _)| n == class) {
                        own.push_str("\n\n");
                        own.push_str(&doc);
                    }
                }
                (Some(class), true) => out.push((format!("{class}.{name}"), doc)),
                _ => out.push((name.to_owned(), doc)),
            }
        }
    }
    out
}

/// The docstring that opens at line `start` (its first line starting with `"""`), without
/// its quotes and with the indentation its lines after the first share taken away (as
/// Python's `inspect.cleandoc` does), so that a class's and its `__init__`'s join evenly.
fn docstring_at(lines: &[&str], start: usize) -> Option<String> {
    let first = lines.get(start)?.trim_start().strip_prefix("\"\"\"")?;
    if let Some(end) = first.find("\"\"\"") {
        return Some(first[..end].trim().to_owned());
    }
    let mut rest: Vec<&str> = Vec::new();
    for line in &lines[start + 1..] {
        if let Some(end) = line.find("\"\"\"") {
            rest.push(&line[..end]);
            let indent = (rest.iter())
                .filter(|l| !l.trim().is_empty())
                .map(|l| l.len() - l.trim_start().len())
                .min()
                .unwrap_or(0);
            let mut doc = first.trim().to_owned();
            for line in rest {
                doc.push('\n');
                doc.push_str(line.get(indent..).unwrap_or("").trim_end());
            }
            return Some(doc.trim_end().to_owned());
        }
        rest.push(line);
    }
    None
}
