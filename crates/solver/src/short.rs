//! Numbers in messages: as written when that is short, else in scientific
//! form (`-1e-300`, not three hundred digits).

use std::fmt;

/// `v` for a message: its plain form up to 12 characters, else the shorter
/// of the plain and the scientific form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Short(pub f64);

impl fmt::Display for Short {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let plain = format!("{}", self.0);
        let sci = format!("{:e}", self.0);
        f.write_str(if plain.len() <= 12 || plain.len() <= sci.len() {
            &plain
        } else {
            &sci
        })
    }
}

/// [`Short`] of `*v` (for error attributes).
pub fn short(v: &f64) -> Short {
    Short(*v)
}

#[cfg(test)]
mod tests {
    use super::Short;

    #[test]
    fn long_numbers_are_scientific() {
        assert_eq!(Short(-1e-300).to_string(), "-1e-300");
        assert_eq!(Short(1e300).to_string(), "1e300");
        assert_eq!(Short(40000.0).to_string(), "40000");
        assert_eq!(Short(0.17).to_string(), "0.17");
        assert_eq!(Short(0.1 + 0.2).to_string(), "0.30000000000000004");
        assert_eq!(Short(1.5e-12).to_string(), "1.5e-12");
        assert_eq!(Short(f64::NAN).to_string(), "NaN");
    }
}
