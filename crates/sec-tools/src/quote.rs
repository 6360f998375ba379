//! Generated tables quoted into a page (REPRODUCTION.md) between two markers, `<!-- KEY: COMMAND -->`
//! on a line of its own and `<!-- /KEY -->`, so that the command that makes a table rewrites its
//! quote in place and a test can check the page against what the command makes.

use std::path::Path;

fn start_marker(key: &str) -> String {
    format!("<!-- {key}: ")
}

fn end_marker(key: &str) -> String {
    format!("<!-- /{key} -->")
}

/// Where the text quoted under `key` lies in `page` (after the start marker's line, up to the end
/// marker), if the page has the markers.
fn span(page: &str, key: &str) -> Option<(usize, usize)> {
    let start = page.find(&format!("\n{}", start_marker(key))).map(|i| i + 1).or_else(|| {
        // The page's first line.
        page.starts_with(&start_marker(key)).then_some(0)
    })?;
    let from = start + page[start..].find('\n')? + 1;
    let len = page[from..].find(&end_marker(key))?;
    Some((from, from + len))
}

/// The text quoted under `key` in `page`.
pub fn quoted<'a>(page: &'a str, key: &str) -> Option<&'a str> {
    span(page, key).map(|(a, b)| &page[a..b])
}

/// The keys of every quote in `page`, in order.
pub fn keys(page: &str) -> Vec<String> {
    page.lines()
        .filter_map(|l| l.strip_prefix("<!-- ")?.strip_suffix(" -->")?.split_once(": ").map(|(k, _)| k.to_string()))
        .filter(|k| !k.starts_with('/') && span(page, k).is_some())
        .collect()
}

/// Replaces the text quoted under `key` in the page at `path` with `md` and a line break (a
/// table's last line break and this one leave a blank line before the end marker).
/// Returns false, leaving the page as it was, when it has no quote of `key`.
pub fn quote_into(path: &Path, key: &str, md: &str) -> Result<bool, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let Some((from, to)) = span(&text, key) else { return Ok(false) };
    let quoted = format!("{}{md}\n{}", &text[..from], &text[to..]);
    std::fs::write(path, quoted).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(true)
}

/// `quote_into`, where the page must have the quote: an error naming the markers it lacks.
pub fn quote_required(path: &Path, key: &str, md: &str) -> Result<(), String> {
    match quote_into(path, key, md)? {
        true => Ok(()),
        false => Err(format!(
            "{}: no quote of '{key}' (a line '<!-- {key}: COMMAND -->' and '<!-- /{key} -->')",
            path.display()
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quotes_are_found_listed_and_replaced_by_key() {
        let page = "# P\n<!-- a/b: make a -->\nold\n<!-- /a/b -->\ntext\n<!-- c: make c -->\n| x |\n<!-- /c -->\n<!-- d: no end -->\n";
        assert_eq!(keys(page), ["a/b", "c"]);
        assert_eq!(quoted(page, "a/b"), Some("old\n"));
        assert_eq!(quoted(page, "c"), Some("| x |\n"));
        assert_eq!(quoted(page, "a"), None);
        let path = std::env::temp_dir().join(format!("sec-quote-test-{}.md", std::process::id()));
        std::fs::write(&path, page).unwrap();
        assert!(quote_into(&path, "a/b", "new\nlines").unwrap());
        assert!(!quote_into(&path, "e", "x").unwrap());
        let e = quote_required(&path, "e", "x").unwrap_err();
        assert!(e.contains("no quote of 'e'"), "{e}");
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text, page.replace("old\n", "new\nlines\n"));
        assert!(quote_into(&path, "a/b", "| t |\n").unwrap());
        assert_eq!(quoted(&std::fs::read_to_string(&path).unwrap(), "a/b"), Some("| t |\n\n"));
        std::fs::remove_file(path).unwrap();
    }
}
