//! Model inputs (thrust, rudder, rpm ...) over time: constants or sampled series, linearly
//! interpolated between samples and held beyond the ends.

/// The inputs of a model over time.
#[derive(Debug, Clone, PartialEq)]
pub struct InputSeries {
    /// Sample times, s (empty when every input is constant).
    pub t: Vec<f64>,
    /// One entry per model input: a constant or a series sampled at `t`.
    pub inputs: Vec<Input>,
}

/// One input.
#[derive(Debug, Clone, PartialEq)]
pub enum Input {
    /// The same value at all times (SI).
    Constant(f64),
    /// Samples at the series' times (SI).
    Series(Vec<f64>),
}

impl InputSeries {
    /// The inputs `wanted` from a record: a column if the record has one, else its constant.
    /// Returns the first input it has neither for.
    pub fn from_record(
        wanted: &[crate::quantity::Quantity],
        rec: &crate::record::Record,
    ) -> Result<Self, crate::quantity::Quantity> {
        let t = rec.time().map(<[f64]>::to_vec).unwrap_or_default();
        let mut inputs = Vec::new();
        for q in wanted {
            let input = match (rec.channel(*q), rec.constants.get(q)) {
                (Some(v), _) => Input::Series(v.to_vec()),
                (None, Some(c)) => Input::Constant(*c),
                (None, None) => return Err(*q),
            };
            inputs.push(input);
        }
        Ok(InputSeries { t, inputs })
    }

    /// Every input constant.
    pub fn constant(values: &[f64]) -> Self {
        InputSeries {
            t: Vec::new(),
            inputs: values.iter().map(|v| Input::Constant(*v)).collect(),
        }
    }

    /// Number of inputs.
    pub fn len(&self) -> usize {
        self.inputs.len()
    }

    /// True when the model has no inputs.
    pub fn is_empty(&self) -> bool {
        self.inputs.is_empty()
    }

    /// The inputs at time `t` into `out`.
    pub fn at(&self, t: f64, out: &mut [f64]) {
        let (i, w) = self.locate(t);
        for (o, input) in out.iter_mut().zip(&self.inputs) {
            *o = match input {
                Input::Constant(v) => *v,
                Input::Series(s) => {
                    if s.len() == 1 {
                        s[0]
                    } else {
                        s[i] + w * (s[i + 1] - s[i])
                    }
                }
            };
        }
    }

    /// Interval index and weight of `t` in the time axis (held at the ends).
    fn locate(&self, t: f64) -> (usize, f64) {
        let ts = &self.t;
        if ts.len() < 2 || t <= ts[0] {
            return (0, 0.0);
        }
        let last = ts.len() - 1;
        if t >= ts[last] {
            return (last - 1, 1.0);
        }
        let i = ts
            .partition_point(|&x| x <= t)
            .saturating_sub(1)
            .min(last - 1);
        let span = ts[i + 1] - ts[i];
        let w = if span > 0.0 { (t - ts[i]) / span } else { 0.0 };
        (i, w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_and_holds() {
        let s = InputSeries {
            t: vec![0.0, 1.0, 2.0],
            inputs: vec![Input::Series(vec![0.0, 10.0, 20.0]), Input::Constant(5.0)],
        };
        let mut o = [0.0; 2];
        s.at(0.25, &mut o);
        assert_eq!(o, [2.5, 5.0]);
        s.at(1.5, &mut o);
        assert_eq!(o, [15.0, 5.0]);
        s.at(-1.0, &mut o);
        assert_eq!(o[0], 0.0);
        s.at(9.0, &mut o);
        assert_eq!(o[0], 20.0);
    }
}
