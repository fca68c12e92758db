//! A last row cut while the file was being written: a solver still writing an export, a copy
//! stopped half-way. Only a last line without a line end can be cut; what it shows decides:
//! a number cut short (`0.`, `1.2e`) or a delimiter with nothing after it is an error, a last
//! value shorter than the column usually is, or with fewer digits, a warning naming the file,
//! line and column (the row is read as it is: it may be whole).

use super::text::Source;
use crate::base::error::InputError;

/// Rows above the last one the column's usual form is taken from.
const ABOVE: usize = 10;

/// The fewest significant digits a column's values must all have for a last value with fewer
/// to be suspect (below it, `0.5` after `0.25` is ordinary).
const MANY_DIGITS: usize = 4;

/// The last cell of a line, without quotes or brackets, a decimal comma read as a point
/// (`-1.25e-3` of `0.1, 2, -1.25e-3`; `1.5` of `0,2;1,5`).
fn last_token(line: &str) -> String {
    let seps: &[char] = if line.contains([';', '\t']) {
        &[';', '\t', ' ']
    } else {
        &[',', ' ', '\t']
    };
    let cell = line.rsplit(seps).next().unwrap_or("");
    cell.trim_matches(|c| matches!(c, '"' | '(' | ')'))
        .replace(',', ".")
}

/// How a number is written: its decimals and the digits of its exponent (`1.250e-03` is
/// (3, Some(2))); `None` for a token that is not a plain number.
fn number_shape(token: &str) -> Option<(usize, Option<usize>)> {
    token.parse::<f64>().ok()?;
    let (mantissa, exponent) = match token.find(['e', 'E']) {
        Some(k) => (
            &token[..k],
            Some(token[k + 1..].trim_start_matches(['+', '-']).len()),
        ),
        None => (token, None),
    };
    let decimals = mantissa.split_once('.').map_or(0, |(_, d)| d.len());
    Some((decimals, exponent))
}

/// The significant digits of a number as written: the digits of its mantissa from the first
/// that is not 0 (`0.0012340` has 5, `1500` 4, `0` none).
fn significant_digits(token: &str) -> usize {
    let mantissa = token.split(['e', 'E']).next().unwrap_or("");
    mantissa
        .bytes()
        .filter(u8::is_ascii_digit)
        .skip_while(|&b| b == b'0')
        .count()
}

/// The error for a last line cut while being written.
fn cut_error(src: &Source, index: usize, what: String) -> InputError {
    InputError::new(
        src.at(index),
        format!("{what}, and has no line end: was the file cut off while being written?"),
    )
    .expected(
        "a complete last line (if the solver is still writing the file, wait for it to \
         finish, or cut the file after the last complete line)",
    )
}

/// A solver still writing a file leaves its last row cut. For a last line without a line end
/// that is the table's last row (`rows` are the 1-based lines of the rows; `column` the name
/// of the table's last column): a number cut short (`0.`, `1.2e`, `3e-`) or a delimiter with
/// nothing after it, where the rows above have a value, is an error; a last value that does
/// not look like the same column in the rows above is a warning naming the file, the line and
/// the column, returned for the table's warnings ([`suspect`] says when).
pub(crate) fn check_cut_off(
    src: &Source,
    rows: &[usize],
    column: Option<&str>,
) -> Result<Option<String>, InputError> {
    match rows.last() {
        Some(&last) if src.unterminated && last == src.lines.len() => {}
        _ => return Ok(None),
    }
    let index = src.lines.len() - 1;
    let trim = |l: &'_ str| l.trim_end_matches([' ', '\r']).to_string();
    let line = trim(src.lines[index]);
    let above: Vec<String> = rows
        .iter()
        .rev()
        .skip(1)
        .take(ABOVE)
        .map(|&l| trim(src.lines[l - 1]))
        .collect();
    if let Some(d) = line
        .chars()
        .last()
        .filter(|c| matches!(c, ',' | ';' | '\t'))
    {
        if above.first().is_some_and(|a| !a.ends_with(d)) {
            return Err(cut_error(
                src,
                index,
                format!("the last line ends in '{d}' with no value after it"),
            ));
        }
    }
    let token = last_token(&line);
    let numeric = token.bytes().any(|b| b.is_ascii_digit())
        && token
            .bytes()
            .all(|b| b.is_ascii_digit() || matches!(b, b'.' | b'e' | b'E' | b'+' | b'-'));
    if numeric && token.ends_with(['.', 'e', 'E', '+', '-']) {
        return Err(cut_error(
            src,
            index,
            format!("the last line ends in '{token}', a number cut short"),
        ));
    }
    let above: Vec<String> = above.iter().map(|a| last_token(a)).collect();
    Ok(suspect(&token, &above).map(|why| {
        let column = column.map_or_else(String::new, |c| format!(" (column '{c}')"));
        format!(
            "{}: line {} (the last) has no line end and its last value '{token}'{column} {why}: \
             the file may have been cut off while being written; the row is read as it is",
            src.path.display(),
            index + 1,
        )
    }))
}

/// Why the last value `own` of a column looks cut, given the same column's values in the rows
/// above (`above`, nearest first), if it does:
///
/// * written with other decimals or exponent digits than every row above (`1.2` under
///   `1.2345e+01`);
/// * shorter than the column's values, all of one width, with the same sign (`3` under
///   `30`, `71` under `710.8`);
/// * with two or more significant digits fewer than every row above, each written with at
///   least [`MANY_DIGITS`] (`-0.37873` under `%.10g` values such as `-0.3787323653`).
fn suspect(own: &str, above: &[String]) -> Option<String> {
    let own_shape = number_shape(own)?;
    let shapes: Option<Vec<_>> = above.iter().map(|a| number_shape(a)).collect();
    let shapes = shapes?;
    let nearest = above.first()?;
    if shapes.len() >= 2 && shapes.iter().all(|s| *s == shapes[0]) && own_shape != shapes[0] {
        return Some(format!(
            "is written with other digits than the rows above ('{nearest}')"
        ));
    }
    let width = nearest.len();
    let same_sign = |a: &str| a.starts_with('-') == own.starts_with('-');
    if above.len() >= 2
        && above.iter().all(|a| a.len() == width && same_sign(a))
        && own.len() < width
    {
        return Some(format!(
            "is shorter than the column's values in the rows above ({width} characters, \
             '{nearest}')"
        ));
    }
    let fewest = above.iter().map(|a| significant_digits(a)).min()?;
    let digits = significant_digits(own);
    // two fewer at least: a column written to N significant digits drops a trailing zero
    // now and then (`%.10g` writes 0.25 as 0.25), two in a hundred rows
    if above.len() >= 3 && fewest >= MANY_DIGITS && digits + 2 <= fewest {
        return Some(format!(
            "has {digits} significant digits where the column's values in the rows above have \
             {fewest} or more ('{nearest}')"
        ));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn above(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn what_a_cut_last_value_looks_like() {
        let constant = above(&["30", "30", "30"]);
        assert!(suspect("3", &constant).unwrap().contains("shorter"));
        assert!(suspect("30", &constant).is_none());
        let rpm = above(&["710.8", "710.8"]);
        assert!(suspect("71", &rpm).unwrap().contains("other digits"));
        let g10 = above(&[
            "-0.3787323653",
            "0.4003949645",
            "1.162115249",
            "17.63309227",
        ]);
        let why = suspect("-0.37873", &g10).unwrap();
        assert!(why.starts_with("has 5 significant digits") && why.contains("10 or more"));
        assert!(suspect("-0.3787323", &g10).is_some());
        assert!(suspect("-0.1234567891", &g10).is_none());
        // one digit fewer is how such a column writes a value ending in 0
        assert!(suspect("-0.378732365", &g10).is_none());
        assert_eq!(significant_digits("0.0012340"), 5);
        assert_eq!(significant_digits("-1.5e+03"), 2);
        assert_eq!(significant_digits("0"), 0);
    }

    #[test]
    fn whole_last_values_are_not_suspect() {
        // a sign change, a value that grows a digit, a column of few digits, a column of
        // varied widths, text
        assert!(suspect("20", &above(&["-20", "-20", "-20"])).is_none());
        assert!(suspect("10", &above(&["9", "8", "7"])).is_none());
        assert!(suspect("2", &above(&["1.5", "1.25"])).is_none());
        assert!(suspect("0.5", &above(&["0.25", "0.125", "0.0625"])).is_none());
        assert!(suspect("7", &above(&["-20", "0", "20"])).is_none());
        assert!(suspect("abc", &above(&["1.0", "2.0"])).is_none());
        assert!(suspect("1.0", &above(&["x", "2.0"])).is_none());
        // one row above says nothing about the column's usual form
        assert!(suspect("3", &above(&["30"])).is_none());
    }
}
