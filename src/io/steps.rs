//! Inputs a configuration gives as `steps` (`steps = [{ time = 10.0, thrust = "30 N" }]`):
//! piecewise-constant values sampled at a record's time stamps.

use crate::base::quantity::Quantity;
use crate::io::input_spec::{InputSpec, Step};

/// One input held between steps, at each of `times`: `start` until the first change, then
/// each change's value from its time on (a change within 1e-12 s after a sample applies from
/// that sample). `changes` are (time, value) in the order they apply.
pub fn stepped(start: f64, changes: &[(f64, f64)], times: &[f64]) -> Vec<f64> {
    // one pass over the times (changes in time order)
    let mut value = start;
    let mut next = changes.iter().peekable();
    times
        .iter()
        .map(|t| {
            while let Some((_, v)) = next.next_if(|(at, _)| *t >= at - 1e-12) {
                value = *v;
            }
            value
        })
        .collect()
}

/// The changes of `q` in `steps`, (time, SI value), in time order (steps at the same time in
/// the order given).
pub fn changes_of(steps: &[Step], q: Quantity) -> Vec<(f64, f64)> {
    let mut changes: Vec<(f64, f64)> = steps
        .iter()
        .filter_map(|s| s.values.get(&q).map(|c| (s.time, c.si)))
        .collect();
    changes.sort_by(|a, b| a.0.total_cmp(&b.0));
    changes
}

/// The quantities an input gives as `steps`, each sampled at the record's time stamps `time`
/// (s) in hydroid's internal unit, starting from its value in `constants`. An error says
/// what is wrong: steps without a time column, a quantity also mapped to a column, or one
/// with no value before its first step.
pub fn sampled_steps(
    spec: &InputSpec,
    time: Option<&[f64]>,
) -> Result<Vec<(Quantity, Vec<f64>)>, String> {
    let mut quantities: Vec<Quantity> = spec
        .steps
        .iter()
        .flat_map(|s| s.values.keys().copied())
        .collect();
    quantities.sort();
    quantities.dedup();
    if quantities.is_empty() {
        return Ok(Vec::new());
    }
    let Some(time) = time.filter(|t| !t.is_empty()) else {
        return Err("`steps` need a time column to be sampled at".into());
    };
    let mut out = Vec::new();
    for q in quantities {
        if spec.columns.contains_key(&q) {
            return Err(format!(
                "{q} is given both as a column and as steps: keep one"
            ));
        }
        let changes = changes_of(&spec.steps, q);
        let start = match spec.constants.get(&q) {
            Some(c) => c.si,
            None if changes[0].0 <= time[0] + 1e-12 => changes[0].1,
            None => {
                return Err(format!(
                    "{q} changes first at {} s but the run starts at {} s: give its value from \
                     the start in `constants` ({q} = ...) or a step at the start",
                    changes[0].0, time[0]
                ))
            }
        };
        let factor = q.internal_unit().factor;
        let values = stepped(start, &changes, time)
            .into_iter()
            .map(|v| v / factor)
            .collect();
        out.push((q, values));
    }
    Ok(out)
}
