//! What the reports say: the [`Document`] built from a run's result and its figures, one
//! module per part (overview, coefficients, each stage, re-simulation, closing notes).

mod captive;
mod closing;
mod coefficients;
mod fmt;
mod hekf;
mod overview;
mod polar;
mod resim;
mod surge;

use super::doc::Document;
use super::plots::Figure;
use crate::app::results::RunResult;
use std::cell::RefCell;

pub use fmt::p_value;

/// The figures, handed out to the sections that show them, each once.
pub(crate) struct Figures<'a> {
    all: &'a [Figure],
    placed: RefCell<Vec<usize>>,
}

impl<'a> Figures<'a> {
    fn new(all: &'a [Figure]) -> Self {
        Figures {
            all,
            placed: RefCell::new(Vec::new()),
        }
    }

    /// Adds the figure called `name` (if it exists and was not placed yet).
    pub(crate) fn put(&self, d: &mut Document<'a>, name: &str) {
        self.put_where(d, |f| f.meta.name == name);
    }

    /// Adds every figure whose name starts with `prefix`, in order.
    pub(crate) fn put_prefixed(&self, d: &mut Document<'a>, prefix: &str) {
        self.put_where(d, |f| f.meta.name.starts_with(prefix));
    }

    fn put_where(&self, d: &mut Document<'a>, pick: impl Fn(&Figure) -> bool) {
        for (i, f) in self.all.iter().enumerate() {
            if pick(f) && !self.placed.borrow().contains(&i) {
                self.placed.borrow_mut().push(i);
                d.figure(f);
            }
        }
    }

    /// The figures no section placed.
    fn rest(&self) -> Vec<&'a Figure> {
        let placed = self.placed.borrow();
        (0..self.all.len())
            .filter(|i| !placed.contains(i))
            .map(|i| &self.all[i])
            .collect()
    }
}

/// The report of a run. `figures` is None when plots are off (the report then says so and
/// shows none).
pub fn document<'a>(r: &'a RunResult, figures: Option<&'a [Figure]>) -> Document<'a> {
    let title = r
        .title
        .clone()
        .unwrap_or_else(|| format!("hydroid report: {}", r.vehicle.name));
    let mut d = Document::new(title);
    let figs = Figures::new(figures.unwrap_or(&[]));
    overview::write(&mut d, r, figures.is_some());
    coefficients::write(&mut d, r, &figs);
    if let Some(p) = &r.stages.polar {
        let word = crate::app::results::data_word(&r.inputs, "polar.").unwrap_or("CFD");
        polar::write(&mut d, p, word, &figs);
    }
    if let Some(s) = &r.stages.surge {
        surge::write(&mut d, s, &figs);
    }
    if let Some(c) = &r.stages.captive {
        captive::write(&mut d, c);
    }
    if let Some(h) = &r.stages.hekf {
        hekf::write(&mut d, h, &figs);
    }
    resim::write(&mut d, r, &figs);
    let rest = figs.rest();
    if !rest.is_empty() {
        d.heading(2, "More figures");
        for f in rest {
            d.figure(f);
        }
    }
    closing::write(&mut d, r, figures);
    d
}
