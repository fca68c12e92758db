//! A small document model for the reports: report.md and report.html are two renderings of
//! the same [`Document`], so they always say the same thing.

use super::plots::Figure;

/// A piece of running text.
#[derive(Debug, Clone, PartialEq)]
pub enum Inline {
    /// Plain text (escaped by the renderer).
    Text(String),
    /// Code or a file name, in a fixed-width face.
    Code(String),
    /// Emphasised text.
    Strong(String),
}

/// Plain text.
pub fn text(s: impl Into<String>) -> Inline {
    Inline::Text(s.into())
}

/// Code.
pub fn code(s: impl Into<String>) -> Inline {
    Inline::Code(s.into())
}

/// Emphasised text.
pub fn strong(s: impl Into<String>) -> Inline {
    Inline::Strong(s.into())
}

/// How a table column is laid out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Col {
    /// Short labels and values: left, kept on one line.
    #[default]
    Tag,
    /// Running text: left, wrapped.
    Text,
    /// Numbers: right-aligned, kept on one line.
    Num,
}

/// A table of plain-text cells.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    /// Column headers.
    pub header: Vec<String>,
    /// Rows, each as long as the header.
    pub rows: Vec<Vec<String>>,
    /// Layout per column (missing: [`Col::Tag`]).
    pub cols: Vec<Col>,
    /// Rows to highlight (flags, inconsistencies), by index.
    pub marked: Vec<usize>,
}

impl Table {
    /// A table with the given headers, every column a [`Col::Tag`].
    pub fn new<S: Into<String>>(header: impl IntoIterator<Item = S>) -> Self {
        let header: Vec<String> = header.into_iter().map(Into::into).collect();
        Table {
            cols: vec![Col::Tag; header.len()],
            header,
            ..Default::default()
        }
    }

    /// Sets the layout of column `i`.
    pub fn col(mut self, i: usize, c: Col) -> Self {
        if let Some(x) = self.cols.get_mut(i) {
            *x = c;
        }
        self
    }

    /// Makes the columns from `first` on numeric.
    pub fn numeric_from(mut self, first: usize) -> Self {
        for c in self.cols.iter_mut().skip(first) {
            *c = Col::Num;
        }
        self
    }

    /// The layout of column `i`.
    pub fn layout(&self, i: usize) -> Col {
        self.cols.get(i).copied().unwrap_or_default()
    }

    /// Adds a row.
    pub fn row<S: Into<String>>(&mut self, cells: impl IntoIterator<Item = S>) {
        self.rows.push(cells.into_iter().map(Into::into).collect());
    }

    /// Adds a highlighted row.
    pub fn marked_row<S: Into<String>>(&mut self, cells: impl IntoIterator<Item = S>) {
        self.marked.push(self.rows.len());
        self.row(cells);
    }
}

/// A block of the document.
#[derive(Debug, Clone, PartialEq)]
pub enum Block<'a> {
    /// A section heading (level 2 or 3; the title is level 1).
    Heading(u8, String),
    /// A paragraph.
    Para(Vec<Inline>),
    /// A bulleted list.
    List(Vec<Vec<Inline>>),
    /// A table.
    Table(Table),
    /// A figure with its number.
    Figure(usize, &'a Figure),
}

/// A whole report.
#[derive(Debug, Clone, PartialEq)]
pub struct Document<'a> {
    /// Title.
    pub title: String,
    /// The content.
    pub blocks: Vec<Block<'a>>,
}

impl<'a> Document<'a> {
    /// An empty document.
    pub fn new(title: impl Into<String>) -> Self {
        Document {
            title: title.into(),
            blocks: Vec::new(),
        }
    }

    /// Adds a section heading.
    pub fn heading(&mut self, level: u8, s: impl Into<String>) {
        self.blocks.push(Block::Heading(level, s.into()));
    }

    /// Adds a paragraph.
    pub fn para(&mut self, inlines: impl IntoIterator<Item = Inline>) {
        self.blocks.push(Block::Para(inlines.into_iter().collect()));
    }

    /// Adds a paragraph of plain text.
    pub fn text(&mut self, s: impl Into<String>) {
        self.para([text(s)]);
    }

    /// Adds a list (nothing when empty).
    pub fn list(&mut self, items: Vec<Vec<Inline>>) {
        if !items.is_empty() {
            self.blocks.push(Block::List(items));
        }
    }

    /// Adds a table (nothing when it has no rows).
    pub fn table(&mut self, t: Table) {
        if !t.rows.is_empty() {
            self.blocks.push(Block::Table(t));
        }
    }

    /// Adds a figure, numbered in order of appearance.
    pub fn figure(&mut self, f: &'a Figure) {
        let n = 1 + self
            .blocks
            .iter()
            .filter(|b| matches!(b, Block::Figure(..)))
            .count();
        self.blocks.push(Block::Figure(n, f));
    }

    /// The figures in order.
    pub fn figures(&self) -> impl Iterator<Item = &'a Figure> + '_ {
        self.blocks.iter().filter_map(|b| match b {
            Block::Figure(_, f) => Some(*f),
            _ => None,
        })
    }
}
