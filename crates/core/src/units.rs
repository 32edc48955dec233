//! Length units of a height field (#24): what its spacing, origin and heights
//! are measured in. Synthetic surfaces have none (the default); measured data
//! read from a metrology format carry theirs, and `--xy-unit`/`--z-unit` set
//! them. Formats that want base units (Gwyddion's GSF and `Gwy::` keys) get
//! metres, the numbers scaled by [`LengthUnit::metres`].

use std::fmt;

/// A length unit: none, or metres with an SI prefix.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LengthUnit {
    /// Unitless (synthetic data).
    #[default]
    None,
    /// Metres.
    M,
    /// Millimetres.
    Mm,
    /// Micrometres.
    Um,
    /// Nanometres.
    Nm,
}

impl LengthUnit {
    /// Every unit, in the order the CLI lists them.
    pub const ALL: [LengthUnit; 5] = [
        LengthUnit::M,
        LengthUnit::Mm,
        LengthUnit::Um,
        LengthUnit::Nm,
        LengthUnit::None,
    ];

    /// `m`, `mm`, `µm` (also `um`, `μm`), `nm`, or `none` (also empty).
    ///
    /// # Errors
    /// A message naming the accepted units.
    pub fn parse(text: &str) -> Result<Self, String> {
        Ok(match text.trim() {
            "m" => LengthUnit::M,
            "mm" => LengthUnit::Mm,
            "µm" | "um" | "μm" => LengthUnit::Um,
            "nm" => LengthUnit::Nm,
            "none" | "" => LengthUnit::None,
            other => {
                return Err(format!(
                    "unknown length unit {other:?} (m, mm, µm, nm or none)"
                ));
            }
        })
    }

    /// The symbol: `m`, `mm`, `µm`, `nm`, or empty for none.
    pub fn symbol(self) -> &'static str {
        match self {
            LengthUnit::None => "",
            LengthUnit::M => "m",
            LengthUnit::Mm => "mm",
            LengthUnit::Um => "µm",
            LengthUnit::Nm => "nm",
        }
    }

    /// The symbol in ASCII (`um` for µm), for file headers that want ASCII;
    /// `none` for unitless.
    pub fn ascii(self) -> &'static str {
        match self {
            LengthUnit::Um => "um",
            LengthUnit::None => "none",
            u => u.symbol(),
        }
    }

    /// Metres per unit; `None` for unitless data.
    pub fn metres(self) -> Option<f64> {
        match self {
            LengthUnit::None => None,
            LengthUnit::M => Some(1.0),
            LengthUnit::Mm => Some(1e-3),
            LengthUnit::Um => Some(1e-6),
            LengthUnit::Nm => Some(1e-9),
        }
    }
}

impl fmt::Display for LengthUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LengthUnit::None => f.write_str("none"),
            u => f.write_str(u.symbol()),
        }
    }
}

/// The lateral (x, y) and height (z) units of a height field.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Units {
    /// Unit of x, y, the spacing and the origin.
    pub xy: LengthUnit,
    /// Unit of the heights.
    pub z: LengthUnit,
}

impl Units {
    /// Lengths and heights in one unit (most instruments' files).
    pub const fn same(unit: LengthUnit) -> Self {
        Self { xy: unit, z: unit }
    }

    /// Whether both are unitless.
    pub fn is_none(&self) -> bool {
        self.xy == LengthUnit::None && self.z == LengthUnit::None
    }

    /// Metres per unit of (xy, z), 1 for a unitless side: what formats that
    /// store base units (GSF, .gwy, x3p) multiply by.
    pub fn metre_factors(&self) -> (f64, f64) {
        (
            self.xy.metres().unwrap_or(1.0),
            self.z.metres().unwrap_or(1.0),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_parse_their_symbols_and_scale_to_metres() {
        for u in LengthUnit::ALL {
            assert_eq!(LengthUnit::parse(&u.to_string()), Ok(u));
            assert_eq!(LengthUnit::parse(u.symbol()), Ok(u));
        }
        assert_eq!(LengthUnit::parse("um"), Ok(LengthUnit::Um));
        for u in LengthUnit::ALL {
            assert_eq!(LengthUnit::parse(u.ascii()), Ok(u));
            assert!(u.ascii().is_ascii());
        }
        assert_eq!(LengthUnit::Um.metres(), Some(1e-6));
        assert_eq!(LengthUnit::None.metres(), None);
        assert!(
            LengthUnit::parse("furlong")
                .unwrap_err()
                .contains("m, mm, µm, nm or none")
        );
    }
}

#[cfg(test)]
mod conversion_tests {
    use crate::{HeightField, LengthUnit, Units};

    #[test]
    fn a_field_with_units_is_converted_a_unitless_one_labelled() {
        let h = HeightField::from_vec([2, 1], vec![1.0, 2.0])
            .unwrap()
            .with_spacing([0.5, 0.5])
            .unwrap();
        let um = Units {
            xy: LengthUnit::Um,
            z: LengthUnit::Nm,
        };
        let labelled = h.clone().in_units(um);
        assert_eq!(
            (labelled.spacing(), labelled.data()),
            ([0.5, 0.5], &[1.0, 2.0][..])
        );
        let metres = labelled.in_units(Units {
            xy: LengthUnit::M,
            z: LengthUnit::M,
        });
        assert!((metres.spacing()[0] - 0.5e-6).abs() < 1e-18);
        assert!((metres.data()[1] - 2e-9).abs() < 1e-21);
        assert_eq!(metres.units().xy, LengthUnit::M);
    }
}
