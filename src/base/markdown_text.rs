//! Markdown written by hydroid (report.md, docs/coefficients.md): escaped text and tables.

/// Escapes the characters that Markdown would read as markup.
pub fn escape_markdown(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '\\' | '`' | '*' | '_' | '[' | ']' | '<' | '>' | '|' | '#' => {
                out.push('\\');
                out.push(ch);
            }
            '\n' | '\r' => out.push(' '),
            _ => out.push(ch),
        }
    }
    out
}

/// A Markdown table; `right[i]` right-aligns column i. Cells are escaped.
pub fn markdown_table(header: &[String], rows: &[Vec<String>], right: &[bool]) -> String {
    let line = |cells: &[String]| {
        let mut s = String::from("|");
        for c in cells {
            s.push_str(&format!(" {} |", escape_markdown(c)));
        }
        s.push('\n');
        s
    };
    let mut s = line(header);
    s.push('|');
    for i in 0..header.len() {
        s.push_str(if right.get(i).copied().unwrap_or(false) {
            "---:|"
        } else {
            "---|"
        });
    }
    s.push('\n');
    for r in rows {
        s.push_str(&line(r));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markdown_cells_cannot_break_the_table() {
        let t = markdown_table(
            &["a|b".to_string(), "n".to_string()],
            &[vec!["x*y_z <b>".to_string(), "1\n2".to_string()]],
            &[false, true],
        );
        assert_eq!(
            t,
            "| a\\|b | n |\n|---|---:|\n| x\\*y\\_z \\<b\\> | 1 2 |\n"
        );
    }
}
