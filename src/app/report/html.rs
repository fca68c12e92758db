//! report.html: the document as one self-contained page (inline CSS, figures as inline SVG,
//! no scripts, no external fonts or links to the network; a Content-Security-Policy forbids
//! loading anything).

use super::doc::{Block, Col, Document, Inline};

/// Escapes text for HTML content and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(ch),
        }
    }
    out
}

/// An anchor name for a heading.
fn slug(s: &str, taken: &mut Vec<String>) -> String {
    let mut base: String = s
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    while base.contains("--") {
        base = base.replace("--", "-");
    }
    let base = base.trim_matches('-').to_string();
    let base = if base.is_empty() {
        "section".into()
    } else {
        base
    };
    let mut id = base.clone();
    let mut k = 2;
    while taken.contains(&id) {
        id = format!("{base}-{k}");
        k += 1;
    }
    taken.push(id.clone());
    id
}

fn inline(i: &Inline) -> String {
    match i {
        Inline::Text(s) => escape(s),
        Inline::Code(s) => format!("<code>{}</code>", escape(s)),
        Inline::Strong(s) => format!("<strong>{}</strong>", escape(s)),
    }
}

fn inlines(v: &[Inline]) -> String {
    v.iter().map(inline).collect()
}

/// The SVG of a figure prepared for inlining: no XML declaration, no namespace URL (HTML
/// does not need it), labelled for screen readers.
pub fn inline_svg(svg: &str, label: &str) -> String {
    let start = svg.find("<svg").unwrap_or(0);
    let body = &svg[start..];
    let body = body.replacen(" xmlns=\"http://www.w3.org/2000/svg\"", "", 1);
    body.replacen(
        "<svg",
        &format!("<svg role=\"img\" aria-label=\"{}\"", escape(label)),
        1,
    )
}

const CSS: &str = r#"
:root { --fg: #1d232a; --muted: #5b6670; --line: #d7dce1; --head: #f1f4f6; --mark: #fff1d6; --accent: #0072b2; }
* { box-sizing: border-box; }
body { margin: 0; color: var(--fg); background: #fff;
  font: 16px/1.55 system-ui, -apple-system, "Segoe UI", Roboto, "DejaVu Sans", sans-serif; }
main { max-width: 1320px; margin: 0 auto; padding: 28px 32px 80px; }
h1 { font-size: 1.85em; line-height: 1.25; margin: 0.2em 0 0.5em; }
h2 { font-size: 1.4em; margin: 2.2em 0 0.6em; padding-bottom: 0.25em; border-bottom: 2px solid var(--line); }
h3 { font-size: 1.15em; margin: 1.7em 0 0.5em; }
p, li { max-width: 78ch; }
a { color: var(--accent); }
nav.toc { background: var(--head); border: 1px solid var(--line); border-radius: 6px; padding: 0.6em 1.2em; margin: 1em 0 1.5em; }
nav.toc ol { margin: 0.3em 0; padding-left: 1.4em; columns: 2; }
.table-wrap { overflow-x: auto; margin: 0.8em 0 1.4em; }
table { border-collapse: collapse; font-size: 0.88em; font-variant-numeric: tabular-nums; }
th, td { border: 1px solid var(--line); padding: 0.35em 0.65em; vertical-align: top; }
th { background: var(--head); text-align: left; vertical-align: bottom; }
td.t { white-space: nowrap; }
td.n { text-align: right; white-space: nowrap; }
td.x > div { min-width: 14em; }
tbody tr:nth-child(even) td { background: #fafbfc; }
tbody tr.mark td { background: var(--mark); }
code { font-family: ui-monospace, "DejaVu Sans Mono", Menlo, Consolas, monospace; font-size: 0.88em;
  background: var(--head); padding: 0 0.25em; border-radius: 3px; overflow-wrap: anywhere; }
figure { margin: 1.6em 0 2em; }
figure svg { display: block; width: 100%; height: auto; border: 1px solid var(--line); border-radius: 4px; }
figcaption { color: var(--muted); font-size: 0.92em; margin-top: 0.5em; max-width: 100ch; }
footer { color: var(--muted); font-size: 0.85em; margin-top: 3em; }
@media print { main { max-width: none; padding: 0; } figure { break-inside: avoid; } nav.toc { display: none; } }
"#;

/// The document as a self-contained HTML page.
pub fn render(doc: &Document) -> String {
    let mut taken = Vec::new();
    let ids: Vec<Option<String>> = doc
        .blocks
        .iter()
        .map(|b| match b {
            Block::Heading(_, t) => Some(slug(t, &mut taken)),
            _ => None,
        })
        .collect();
    let mut body = String::new();
    let mut toc = String::new();
    for (b, id) in doc.blocks.iter().zip(&ids) {
        match b {
            Block::Heading(level, t) => {
                let l = (*level).clamp(2, 6);
                let id = id.as_deref().unwrap_or("section");
                if l == 2 {
                    toc.push_str(&format!("<li><a href=\"#{id}\">{}</a></li>", escape(t)));
                }
                body.push_str(&format!("<h{l} id=\"{id}\">{}</h{l}>\n", escape(t)));
            }
            Block::Para(v) => body.push_str(&format!("<p>{}</p>\n", inlines(v))),
            Block::List(items) => {
                body.push_str("<ul>\n");
                for it in items {
                    body.push_str(&format!("<li>{}</li>\n", inlines(it)));
                }
                body.push_str("</ul>\n");
            }
            Block::Table(t) => {
                body.push_str("<div class=\"table-wrap\"><table>\n<thead><tr>");
                for h in &t.header {
                    body.push_str(&format!("<th>{}</th>", escape(h)));
                }
                body.push_str("</tr></thead>\n<tbody>\n");
                for (i, row) in t.rows.iter().enumerate() {
                    if t.marked.contains(&i) {
                        body.push_str("<tr class=\"mark\">");
                    } else {
                        body.push_str("<tr>");
                    }
                    for (j, c) in row.iter().enumerate() {
                        let class = match t.layout(j) {
                            Col::Tag => "t",
                            Col::Text => "x",
                            Col::Num => "n",
                        };
                        if class == "x" {
                            body.push_str(&format!(
                                "<td class=\"x\"><div>{}</div></td>",
                                escape(c)
                            ));
                        } else {
                            body.push_str(&format!("<td class=\"{class}\">{}</td>", escape(c)));
                        }
                    }
                    body.push_str("</tr>\n");
                }
                body.push_str("</tbody>\n</table></div>\n");
            }
            Block::Figure(n, f) => {
                body.push_str(&format!(
                    "<figure id=\"fig-{name}\"{shows}>\n{svg}\n<figcaption><strong>Figure {n}. {title}.</strong> \
                     {caption} <a href=\"{svg_path}\">SVG</a> · <a href=\"{png_path}\">PNG</a></figcaption>\n</figure>\n",
                    name = escape(&f.meta.name),
                    shows = if f.meta.shows.is_empty() {
                        String::new()
                    } else {
                        format!(" data-shows=\"{}\"", escape(&f.meta.shows.join(" ")))
                    },
                    svg = inline_svg(&f.svg, &f.meta.title),
                    title = escape(&f.meta.title),
                    caption = escape(&f.meta.caption),
                    svg_path = escape(&f.svg_path()),
                    png_path = escape(&f.png_path()),
                ));
            }
        }
    }
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; style-src 'unsafe-inline'; img-src data:\">\n\
         <title>{title}</title>\n<style>{CSS}</style>\n</head>\n<body>\n<main>\n<h1>{title}</h1>\n\
         <nav class=\"toc\" aria-label=\"Contents\"><strong>Contents</strong><ol>{toc}</ol></nav>\n\
         {body}<footer>Written by hydroid {version}. This page is self-contained: it loads nothing from \
         anywhere.</footer>\n</main>\n</body>\n</html>\n",
        title = escape(&doc.title),
        version = env!("CARGO_PKG_VERSION"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::report::doc::{text, Table};
    use crate::app::report::plots::{Figure, FigureMeta, Section};

    #[test]
    fn text_from_files_is_escaped() {
        assert_eq!(
            escape("<script>alert('x') & \"y\"</script>"),
            "&lt;script&gt;alert(&#39;x&#39;) &amp; &quot;y&quot;&lt;/script&gt;"
        );
        let mut d = Document::new("<b>title</b>");
        d.heading(2, "Runs & <inputs>");
        d.para([text("run '<img src=x onerror=1>'")]);
        let mut t = Table::new(["a<b"]);
        t.marked_row(["</td><script>"]);
        d.table(t);
        let h = render(&d);
        assert!(!h.contains("<b>title"));
        assert!(!h.contains("<img"));
        assert!(!h.contains("<script>"));
        assert!(h.contains("<h2 id=\"runs-inputs\">Runs &amp; &lt;inputs&gt;</h2>"));
        assert!(
            h.contains("<tr class=\"mark\"><td class=\"t\">&lt;/td&gt;&lt;script&gt;</td></tr>")
        );
        assert!(h.contains("<a href=\"#runs-inputs\">"));
    }

    #[test]
    fn figures_are_inlined_without_namespace_urls() {
        let svg = "<?xml version=\"1.0\"?>\n<svg width=\"10\" height=\"10\" viewBox=\"0 0 10 10\" \
                   xmlns=\"http://www.w3.org/2000/svg\"><text>a &amp; b</text></svg>";
        let fig = Figure {
            meta: FigureMeta {
                name: "x".into(),
                title: "T \"q\"".into(),
                caption: "c".into(),
                section: Section::Polar,
                shows: Vec::new(),
            },
            svg: svg.into(),
        };
        let mut d = Document::new("t");
        d.figure(&fig);
        let h = render(&d);
        assert!(!h.contains("http://") && !h.contains("https://"), "{h}");
        assert!(!h.contains("<?xml"));
        assert!(h.contains("<svg role=\"img\" aria-label=\"T &quot;q&quot;\" width=\"10\""));
        assert!(h.contains("<figure id=\"fig-x\">"));
        assert_eq!(h.matches("<svg").count(), 1);
    }

    #[test]
    fn heading_anchors_are_unique() {
        let mut taken = Vec::new();
        assert_eq!(slug("Re-simulation", &mut taken), "re-simulation");
        assert_eq!(slug("Re-simulation", &mut taken), "re-simulation-2");
        assert_eq!(slug("±", &mut taken), "section");
    }
}
