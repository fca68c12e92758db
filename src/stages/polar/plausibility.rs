//! Cheap checks of a polar's angles before they are trusted: angles in radians under a degree
//! label give a sweep of a fraction of a degree and slopes 57.3 times too large at R^2 = 1;
//! angles in degrees under a radian label fall outside any fitting range.

use super::data::PolarPoint;
use super::STAGE;
use crate::base::warning::Warning;

/// A drift sweep narrower than this (deg) is almost certainly radians read as degrees.
const NARROWEST_SWEEP_DEG: f64 = 1.0;

/// Warns when the fitted angles span less than a degree although several distinct angles
/// were run: the signature of radians labelled as degrees.
pub fn alpha_range(used: &[&PolarPoint]) -> Option<Warning> {
    let mut alphas: Vec<f64> = used.iter().map(|p| p.alpha_deg).collect();
    alphas.sort_by(f64::total_cmp);
    alphas.dedup();
    let (lo, hi) = (*alphas.first()?, *alphas.last()?);
    let peak = lo.abs().max(hi.abs());
    (alphas.len() >= 3 && peak > 0.0 && peak < NARROWEST_SWEEP_DEG).then(|| {
        Warning::new(
            STAGE,
            format!(
                "the drift angles span only {lo:.3} to {hi:.3} deg over {} distinct angles; as \
                 radians they would span {:.1} to {:.1} deg",
                alphas.len(),
                lo.to_degrees(),
                hi.to_degrees()
            ),
            "if the column holds radians under a degree label, every slope (Yuvl, Nuvl, Yuvd, \
             the drag parabola) is 57.3 times too large although the fit looks perfect: give \
             the column's unit in the configuration, e.g. `alpha = { name = \"...\", unit = \
             \"rad\" }`",
        )
    })
}

/// A hint for the error when no point lies within the fitting range: angles beyond 90 deg
/// that would lie within it as degrees were probably degrees labelled as radians.
pub fn degrees_as_radians_hint(points: &[PolarPoint]) -> String {
    let as_degrees_inside = points.iter().filter(|p| p.alpha.abs() <= 90.0).count();
    if !points.is_empty() && as_degrees_inside == points.len() {
        let hi = points.iter().map(|p| p.alpha.abs()).fold(0.0, f64::max);
        format!(
            " (the angles reach {:.0} deg; read as degrees they would reach {hi:.1} deg: is \
             the column in degrees under a radian label? give `unit = \"deg\"` for it)",
            hi.to_degrees()
        )
    } else {
        String::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(alpha_deg: f64) -> PolarPoint {
        PolarPoint {
            record: "sweep".into(),
            line: None,
            alpha: alpha_deg.to_radians(),
            alpha_deg,
            speed: Some(2.0),
            cd: 0.1,
            cl: 0.0,
            cm: 0.0,
            cd_se: None,
            cl_se: None,
            cm_se: None,
            samples: 1,
            used: true,
        }
    }

    #[test]
    fn radians_under_a_degree_label_are_named() {
        // a +-20 deg sweep given in radians but read as degrees
        let pts: Vec<PolarPoint> = [-0.349, -0.175, 0.0, 0.175, 0.349]
            .into_iter()
            .map(point)
            .collect();
        let refs: Vec<&PolarPoint> = pts.iter().collect();
        let w = alpha_range(&refs).expect("flagged");
        assert!(w.message.contains("-20.0 to 20.0 deg"), "{}", w.message);
        assert!(w.meaning.contains("57.3"), "{}", w.meaning);
        // a real sweep is not
        let pts: Vec<PolarPoint> = [-20.0, -10.0, 0.0, 10.0, 20.0]
            .into_iter()
            .map(point)
            .collect();
        let refs: Vec<&PolarPoint> = pts.iter().collect();
        assert!(alpha_range(&refs).is_none());
    }

    #[test]
    fn degrees_under_a_radian_label_get_a_hint() {
        // +-20 "rad": 1146 deg
        let pts: Vec<PolarPoint> = [-20.0f64, 0.5, 20.0]
            .into_iter()
            .map(|a| point(a.to_degrees()))
            .collect();
        let h = degrees_as_radians_hint(&pts);
        assert!(h.contains("degrees under a radian label"), "{h}");
        assert!(degrees_as_radians_hint(&[point(200.0)]).contains("degrees"));
        assert_eq!(degrees_as_radians_hint(&[point(20000.0)]), "");
    }
}
