//! report.md: the document in Markdown, figures linked as `plots/NAME.svg`.

use super::doc::{Block, Col, Document, Inline};
use crate::base::markdown_text::{escape_markdown, markdown_table};

fn inline(i: &Inline) -> String {
    match i {
        Inline::Text(s) => escape_markdown(s),
        Inline::Code(s) => {
            let s = s.replace(['\n', '\r'], " ");
            if s.contains('`') {
                format!("`` {s} ``")
            } else {
                format!("`{s}`")
            }
        }
        Inline::Strong(s) => format!("**{}**", escape_markdown(s)),
    }
}

fn inlines(v: &[Inline]) -> String {
    v.iter().map(inline).collect()
}

/// The document as Markdown.
pub fn render(doc: &Document) -> String {
    let mut s = format!("# {}\n\n", escape_markdown(&doc.title));
    for b in &doc.blocks {
        match b {
            Block::Heading(level, t) => {
                s.push_str(&format!(
                    "{} {}\n\n",
                    "#".repeat((*level).clamp(2, 6) as usize),
                    escape_markdown(t)
                ));
            }
            Block::Para(v) => {
                s.push_str(&inlines(v));
                s.push_str("\n\n");
            }
            Block::List(items) => {
                for it in items {
                    s.push_str(&format!("- {}\n", inlines(it)));
                }
                s.push('\n');
            }
            Block::Table(t) => {
                let right: Vec<bool> = (0..t.header.len())
                    .map(|i| t.layout(i) == Col::Num)
                    .collect();
                s.push_str(&markdown_table(&t.header, &t.rows, &right));
                s.push('\n');
            }
            Block::Figure(n, f) => {
                s.push_str(&format!(
                    "![Figure {n}: {}]({})\n\n*Figure {n}: {}.* {} ([PNG]({}))\n\n",
                    escape_markdown(&f.meta.title),
                    f.svg_path(),
                    escape_markdown(&f.meta.title),
                    escape_markdown(&f.meta.caption),
                    f.png_path()
                ));
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::report::doc::{code, strong, text, Table};
    use crate::app::report::plots::{Figure, FigureMeta, Section};

    #[test]
    fn blocks_render_as_markdown() {
        let fig = Figure {
            meta: FigureMeta {
                name: "polar".into(),
                title: "Polars".into(),
                caption: "C_D against alpha".into(),
                section: Section::Polar,
                shows: Vec::new(),
            },
            svg: "<svg/>".into(),
        };
        let mut d = Document::new("Run *1*");
        d.heading(2, "Inputs");
        d.para([text("file "), code("a`b.csv"), text(" is "), strong("new")]);
        d.list(vec![vec![text("one")], vec![text("two")]]);
        let mut t = Table::new(["name", "value"]).numeric_from(1);
        t.row(["x", "1.0"]);
        d.table(t);
        d.figure(&fig);
        let md = render(&d);
        assert!(md.starts_with("# Run \\*1\\*\n\n## Inputs\n\n"), "{md}");
        assert!(md.contains("file `` a`b.csv `` is **new**"), "{md}");
        assert!(md.contains("- one\n- two\n"));
        assert!(md.contains("| name | value |\n|---|---:|\n| x | 1.0 |\n"));
        assert!(md.contains("![Figure 1: Polars](plots/polar.svg)"));
        assert!(md.contains("C\\_D against alpha"));
        assert!(md.contains("([PNG](plots/polar.png))"));
    }
}
