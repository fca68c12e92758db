//! "Did you mean ...?" suggestions for misspelt keys, columns, coefficients and units.

/// The candidate closest to `word`, if it is close enough to be a plausible misspelling:
/// case-insensitive Damerau-Levenshtein distance at most a third of the length (at least 2),
/// one containing the other, or Jaro-Winkler similarity of at least 0.8 (abbreviations such
/// as `ref_area`). Ties go to the first candidate.
pub fn nearest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let w = word.trim().to_lowercase();
    let limit = (w.chars().count() / 3).max(2);
    let mut best: Option<(f64, &str)> = None;
    for c in candidates {
        let cl = c.trim().to_lowercase();
        let d = strsim::damerau_levenshtein(&w, &cl);
        let jw = strsim::jaro_winkler(&w, &cl);
        let contains = !w.is_empty() && !cl.is_empty() && (cl.contains(&w) || w.contains(&cl));
        if d > limit && !contains && jw < 0.8 {
            continue;
        }
        // rank: small edit distance first, then similarity
        let score = jw - d as f64;
        if best.is_none_or(|(b, _)| score > b) {
            best = Some((score, c));
        }
    }
    best.map(|(_, c)| c)
}

/// A `did you mean` clause for `word`, or an empty string.
pub fn did_you_mean<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    match nearest(word, candidates) {
        Some(c) => format!("; did you mean '{c}'?"),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_close_names() {
        let keys = ["mass", "length", "diameter", "reference_area"];
        assert_eq!(nearest("masss", keys), Some("mass"));
        assert_eq!(nearest("lenght", keys), Some("length"));
        assert_eq!(nearest("ref_area", keys), Some("reference_area"));
        assert_eq!(nearest("zzzzzzzz", keys), None);
        assert_eq!(
            nearest("Velocity U", ["Velocity u [ m s^-1 ]", "Time"]),
            Some("Velocity u [ m s^-1 ]")
        );
    }
}
