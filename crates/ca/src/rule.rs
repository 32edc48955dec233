//! Cellular-automaton rules in Wolfram's numbering, as Mathematica's
//! `CellularAutomaton` defines them.
//!
//! Paper: [peridier] §"Cellular Automaton Basics", Figure 2 (the look-up table of
//! rule 450) and the enumeration paragraph after it ("rules numbered 0, 1, …,
//! 1023", after Wolfram's ref. \[10\]).
//!
//! # Families
//! A rule maps a weighted sum of the 3×3 (or 5-cell) neighbourhood to the new
//! state: new = digit `s` of the code in base k, where the weights are those of
//! Mathematica's rule specification `{code, {k, weights}, {1, 1}}`:
//!
//! | Family | Mathematica spec | Index s | Codes |
//! | --- | --- | --- | --- |
//! | [`Family::Totalistic9`] | `{n, {k, 1}, {1, 1}}` | sum of the 9 cells, 0…9(k−1) | 0 … k^(9(k−1)+1) − 1 (k = 2: 0…1023) |
//! | [`Family::Totalistic5`] | `{n, {k, {{0,1,0},{1,1,1},{0,1,0}}}, {1, 1}}` | sum of the 5 cells | 0 … k^(5(k−1)+1) − 1 (k = 2: 0…63) |
//! | [`Family::Outer9`] | `{n, {2, {{2,2,2},{2,1,2},{2,2,2}}}, {1, 1}}` | centre + 2·(sum of the 8 others), 0…17 | 0 … 2¹⁸ − 1 (Life = 224) |
//! | [`Family::Outer5`] | `{n, {2, {{0,2,0},{2,1,2},{0,2,0}}}, {1, 1}}` | centre + 2·(sum of the 4 others), 0…9 | 0 … 1023 |
//!
//! Digit s of the code (base k, s = 0 the least significant) is the new state for
//! index s. Golly-style `B3/S23` strings give the equivalent outer-totalistic
//! 9-neighbour code (birth on n neighbours sets digit 2n, survival digit 2n+1).
//!
//! # Deviations from the paper
//! None for the numbering; codes are parsed as `u128`, which bounds k-colour
//! totalistic rules at k ≤ 6 (9-neighbour) and k ≤ 12 (5-neighbour).
//!
//! [peridier]: https://www.mathematica-journal.com/2011/07/facetsurface-representation/ "Peridier: Rough-Surface Simulation and the Visualization of Nonsmooth Arrays of Data. The Mathematica Journal, 2011"

use crate::CaError;

/// Which neighbourhood and weighting a code refers to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// Sum of the 3×3 Moore neighbourhood including the centre.
    Totalistic9,
    /// Sum of the von Neumann neighbourhood (centre and 4 edge neighbours).
    Totalistic5,
    /// Centre + 2 × sum of the 8 Moore neighbours (two states only).
    Outer9,
    /// Centre + 2 × sum of the 4 von Neumann neighbours (two states only).
    Outer5,
}

impl Family {
    /// Parses `totalistic9`, `totalistic5`, `outer9`, `outer5`.
    pub fn from_name(s: &str) -> Option<Self> {
        Some(match s {
            "totalistic9" => Family::Totalistic9,
            "totalistic5" => Family::Totalistic5,
            "outer9" => Family::Outer9,
            "outer5" => Family::Outer5,
            _ => return None,
        })
    }

    /// The CLI name.
    pub fn name(self) -> &'static str {
        match self {
            Family::Totalistic9 => "totalistic9",
            Family::Totalistic5 => "totalistic5",
            Family::Outer9 => "outer9",
            Family::Outer5 => "outer5",
        }
    }

    /// Whether the neighbourhood is the 3×3 block (else the 5-cell cross).
    pub fn moore(self) -> bool {
        matches!(self, Family::Totalistic9 | Family::Outer9)
    }

    /// Number of table entries for `k` states.
    pub fn table_len(self, k: u8) -> usize {
        let k = k as usize;
        match self {
            Family::Totalistic9 => 9 * (k - 1) + 1,
            Family::Totalistic5 => 5 * (k - 1) + 1,
            Family::Outer9 => 18,
            Family::Outer5 => 10,
        }
    }

    /// The table index for a centre value and the sum of the other cells.
    #[inline]
    pub fn index(self, centre: u32, others: u32) -> usize {
        match self {
            Family::Totalistic9 | Family::Totalistic5 => (centre + others) as usize,
            Family::Outer9 | Family::Outer5 => (centre + 2 * others) as usize,
        }
    }
}

/// A rule: family, number of states and the look-up table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rule {
    family: Family,
    k: u8,
    code: u128,
    table: Vec<u8>,
}

impl Rule {
    /// The rule with Wolfram code `code` in `family` with `k` states.
    ///
    /// # Errors
    /// [`CaError::BadRule`] when k is out of range for the family or the code
    /// exceeds the family's largest code.
    pub fn new(family: Family, k: u8, code: u128) -> Result<Self, CaError> {
        let outer = matches!(family, Family::Outer9 | Family::Outer5);
        if k < 2 || (outer && k != 2) {
            return Err(CaError::BadRule(format!(
                "{} rules need {} states, got {k}",
                family.name(),
                if outer { "exactly 2" } else { "at least 2" }
            )));
        }
        let len = family.table_len(k);
        let max = (k as u128).checked_pow(len as u32).map(|m| m - 1);
        let Some(max) = max else {
            return Err(CaError::BadRule(format!(
                "{}-state {} codes do not fit in 128 bits; use fewer states",
                k,
                family.name()
            )));
        };
        if code > max {
            return Err(CaError::BadRule(format!(
                "code {code} is out of range for {k}-state {} rules (0..={max})",
                family.name()
            )));
        }
        let mut table = Vec::with_capacity(len);
        let mut c = code;
        for _ in 0..len {
            table.push((c % k as u128) as u8);
            c /= k as u128;
        }
        Ok(Self {
            family,
            k,
            code,
            table,
        })
    }

    /// Two-state rule from a decimal code string (`"450"`) or a Golly-style
    /// `B3/S23` string (outer-totalistic 9-neighbour).
    ///
    /// # Errors
    /// [`CaError::BadRule`] for anything else.
    pub fn parse(family: Family, k: u8, text: &str) -> Result<Self, CaError> {
        let t = text.trim();
        if t.starts_with(['B', 'b']) {
            return Self::from_bs(t);
        }
        let code: u128 = t.parse().map_err(|_| {
            CaError::BadRule(format!(
                "{t:?} is neither a rule number nor a B/S string like B3/S23"
            ))
        })?;
        Self::new(family, k, code)
    }

    /// A Golly-style `Bxyz/Sxyz` rule as an outer-totalistic 9-neighbour code.
    ///
    /// # Errors
    /// [`CaError::BadRule`] for malformed strings or neighbour counts above 8.
    pub fn from_bs(text: &str) -> Result<Self, CaError> {
        let bad = || CaError::BadRule(format!("{text:?} is not a B/S rule like B3/S23"));
        let upper = text.trim().to_ascii_uppercase();
        let (b, s) = upper.split_once('/').ok_or_else(bad)?;
        let b = b.strip_prefix('B').ok_or_else(bad)?;
        let s = s.strip_prefix('S').ok_or_else(bad)?;
        let mut code = 0u128;
        for (digits, survive) in [(b, 0), (s, 1)] {
            for ch in digits.chars() {
                let n = ch.to_digit(10).filter(|&n| n <= 8).ok_or_else(bad)?;
                code |= 1 << (2 * n + survive);
            }
        }
        Self::new(Family::Outer9, 2, code)
    }

    /// The family.
    pub fn family(&self) -> Family {
        self.family
    }
    /// Number of states k.
    pub fn states(&self) -> u8 {
        self.k
    }
    /// The Wolfram code.
    pub fn code(&self) -> u128 {
        self.code
    }
    /// New state for each table index.
    pub fn table(&self) -> &[u8] {
        &self.table
    }
    /// New state for a centre value and the sum of the other neighbourhood cells.
    #[inline]
    pub fn next(&self, centre: u32, others: u32) -> u8 {
        self.table[self.family.index(centre, others)]
    }

    /// The look-up table as the paper's Figure 2 prints it: indices from the
    /// largest down to 0 above the new states.
    pub fn describe(&self) -> String {
        let idx: Vec<String> = (0..self.table.len()).rev().map(|i| i.to_string()).collect();
        let width = idx.iter().map(String::len).max().unwrap_or(1);
        let row = |v: Vec<String>| {
            v.iter()
                .map(|s| format!("{s:>width$}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        let label = match self.family {
            Family::Totalistic9 | Family::Totalistic5 => "neighbourhood sum",
            Family::Outer9 | Family::Outer5 => "centre + 2·others",
        };
        format!(
            "{}-state {} rule {}\n{label:>18}: {}\n{:>18}: {}\n",
            self.k,
            self.family.name(),
            self.code,
            row(idx),
            "new state",
            row((0..self.table.len())
                .rev()
                .map(|i| self.table[i].to_string())
                .collect())
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rule_450_is_figure_2() {
        // 450 = 2⁸ + 2⁷ + 2⁶ + 2¹: sums 8, 7, 6 and 1 give 1 (the paper's Figure 2).
        let r = Rule::new(Family::Totalistic9, 2, 450).unwrap();
        assert_eq!(r.table(), &[0, 1, 0, 0, 0, 0, 1, 1, 1, 0]);
        assert!(
            r.describe().contains("9 8 7 6 5 4 3 2 1 0")
                && r.describe().contains("0 1 1 1 0 0 0 0 1 0"),
            "{}",
            r.describe()
        );
    }

    #[test]
    fn life_is_224_and_b3s23() {
        let life = Rule::from_bs("B3/S23").unwrap();
        assert_eq!((life.family(), life.code()), (Family::Outer9, 224));
        // Birth with 3 neighbours, survival with 2 or 3, death otherwise.
        assert_eq!(life.next(0, 3), 1);
        assert_eq!(life.next(1, 2), 1);
        assert_eq!(life.next(1, 4), 0);
        assert_eq!(life.next(0, 2), 0);
        assert_eq!(
            Rule::parse(Family::Totalistic9, 2, "b36/s23")
                .unwrap()
                .code(),
            224 | 1 << 12
        );
    }

    #[test]
    fn ranges_and_k_colour() {
        assert!(Rule::new(Family::Totalistic9, 2, 1023).is_ok());
        assert!(
            Rule::new(Family::Totalistic9, 2, 1024)
                .unwrap_err()
                .to_string()
                .contains("0..=1023")
        );
        assert!(Rule::new(Family::Totalistic5, 2, 64).is_err());
        assert!(Rule::new(Family::Outer9, 2, (1 << 18) - 1).is_ok());
        assert!(Rule::new(Family::Outer9, 2, 1 << 18).is_err());
        assert!(Rule::new(Family::Outer5, 2, 1024).is_err());
        assert!(Rule::new(Family::Outer9, 3, 1).is_err());
        // 3-colour totalistic: 19 digits in base 3; code 2·3⁴ + 3 → digits [0, 1, 0, 0, 2, 0…].
        let r = Rule::new(Family::Totalistic9, 3, 2 * 81 + 3).unwrap();
        assert_eq!(r.table().len(), 19);
        assert_eq!(&r.table()[..6], &[0, 1, 0, 0, 2, 0]);
        assert!(Rule::new(Family::Totalistic9, 7, 0).is_err());
        for bad in ["B9/S", "B3S23", "3/23", "x"] {
            assert!(Rule::parse(Family::Totalistic9, 2, bad).is_err(), "{bad}");
        }
    }
}
