//! The value types that job parameters share, each with one form on the
//! command line and one in JSON: windows `A,B`, lattice sizes `NXxNYxNZ`,
//! number lists `a,b,c`, sizes `WxH`.

use schemars::JsonSchema;
use serde::Serialize;

use super::param;
use crate::error::{EngineError, Result};

/// `N` numbers: `a,b,c` on the command line, `[a, b, c]` in JSON (a circle
/// CX,CY,R, a point X,Y,Z, a light AZ,ALT).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Numbers<const N: usize>(pub [f64; N]);

impl<const N: usize> Serialize for Numbers<N> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        self.0.as_slice().serialize(s)
    }
}

impl<'de, const N: usize> serde::Deserialize<'de> for Numbers<N> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let v = Vec::<f64>::deserialize(d)?;
        let len = v.len();
        v.try_into()
            .map(Self)
            .map_err(|_| serde::de::Error::invalid_length(len, &format!("{N} numbers").as_str()))
    }
}

impl<const N: usize> JsonSchema for Numbers<N> {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        format!("Numbers{N}").into()
    }

    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "type": "array",
            "items": {"type": "number", "minimum": -MAX_COORDINATE, "maximum": MAX_COORDINATE},
            "minItems": N,
            "maxItems": N,
        })
    }
}

impl<const N: usize> std::str::FromStr for Numbers<N> {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let v: Vec<f64> = s
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| format!("{s:?} is not {N} numbers separated by commas"))?;
        v.try_into()
            .map(Self)
            .map_err(|_| format!("{s:?} is not {N} numbers separated by commas"))
    }
}

impl<const N: usize> std::fmt::Display for Numbers<N> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let parts: Vec<String> = self.0.iter().map(f64::to_string).collect();
        f.write_str(&parts.join(","))
    }
}

/// The largest magnitude of a coordinate or number given as a list
/// ([`Numbers`]: a camera's eye and target, a light's direction, an operator).
pub const MAX_COORDINATE: f64 = 1e12;

/// The most cells or pixels along one side of a size ([`Size2`],
/// [`LatticeSize`]); the memory and time estimates bound their products.
pub const MAX_SIDE: usize = 1 << 20;

/// A number in a list (weights, heights of states), for the schemas: finite,
/// of magnitude at most [`MAX_COORDINATE`].
#[derive(JsonSchema)]
#[schemars(inline)]
#[allow(dead_code)]
pub(crate) struct Finite(#[schemars(range(min = -MAX_COORDINATE, max = MAX_COORDINATE))] f64);

/// A list of up to 1,000 user values (heights at which a curve is read),
/// for the schemas.
#[derive(JsonSchema)]
#[schemars(inline)]
#[allow(dead_code)]
pub(crate) struct Heights(#[schemars(length(min = 1, max = 1000))] Vec<Finite>);

/// A percentage, 0 to 100, for the schemas.
#[derive(JsonSchema)]
#[schemars(inline)]
#[allow(dead_code)]
pub(crate) struct Percent(#[schemars(range(min = 0.0, max = 100.0))] f64);

/// A list of up to 1,000 percentages, for the schemas.
#[derive(JsonSchema)]
#[schemars(inline)]
#[allow(dead_code)]
pub(crate) struct Percents(#[schemars(length(min = 1, max = 1000))] Vec<Percent>);

/// A length or a time in a list (a fit window's ends), for the schemas: 0
/// to [`MAX_COORDINATE`] (further checked by [`Window::check`]).
#[derive(JsonSchema)]
#[schemars(inline)]
#[allow(dead_code)]
pub(crate) struct NonNegative(#[schemars(range(min = 0.0, max = MAX_COORDINATE))] f64);

/// A positive number up to [`MAX_COORDINATE`] (a spacing), for the schemas.
#[derive(JsonSchema)]
#[schemars(inline)]
#[allow(dead_code)]
pub(crate) struct Positive(
    #[schemars(range(max = MAX_COORDINATE), extend("exclusiveMinimum" = 0.0))] f64,
);

/// A size in cells or pixels, `WxH` on the command line, `[W, H]` in JSON.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize, JsonSchema)]
#[serde(from = "[usize; 2]", into = "[usize; 2]")]
#[schemars(with = "[Side; 2]")]
pub struct Size2(pub [usize; 2]);

/// One side of a size, for the schemas: 1 to [`MAX_SIDE`] (inlined, so a
/// size's items read as integers).
#[derive(JsonSchema)]
#[schemars(inline)]
#[allow(dead_code)]
pub(crate) struct Side(#[schemars(range(min = 1, max = MAX_SIDE))] usize);

impl From<[usize; 2]> for Size2 {
    fn from(v: [usize; 2]) -> Self {
        Self(v)
    }
}

impl From<Size2> for [usize; 2] {
    fn from(v: Size2) -> Self {
        v.0
    }
}

impl std::str::FromStr for Size2 {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let err = || format!("{s:?} is not WIDTHxHEIGHT, e.g. 1024x768");
        let (w, h) = s.split_once(['x', 'X', '×']).ok_or_else(err)?;
        let p = |v: &str| v.trim().parse::<usize>().map_err(|_| err());
        Ok(Self([p(w)?, p(h)?]))
    }
}

impl std::fmt::Display for Size2 {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}", self.0[0], self.0[1])
    }
}

/// Two numbers `A,B`: a fit window (monolayers, or wavenumbers), 0 < A < B
/// ([`Window::check`], called by the jobs that take one). On the command
/// line `A,B`; in JSON `[A, B]`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize, JsonSchema)]
#[serde(from = "[f64; 2]", into = "[f64; 2]")]
#[schemars(with = "[NonNegative; 2]")]
pub struct Window(pub [f64; 2]);

impl From<[f64; 2]> for Window {
    fn from(w: [f64; 2]) -> Self {
        Self(w)
    }
}

impl From<Window> for [f64; 2] {
    fn from(w: Window) -> Self {
        w.0
    }
}

impl Window {
    /// Checks 0 < A < B for the parameter `name`, whose parts are called
    /// `parts` in the message (`TMIN,TMAX`).
    ///
    /// # Errors
    /// [`EngineError::Invalid`] naming the parameter.
    pub fn check(&self, name: &str, parts: &str) -> Result<()> {
        let [a, b] = self.0;
        if a > 0.0 && b > a && b.is_finite() {
            return Ok(());
        }
        let (lo, hi) = parts.split_once(',').unwrap_or(("A", "B"));
        Err(EngineError::Invalid(format!(
            "{} takes {parts} with 0 < {lo} < {hi}, got {:?}",
            param(name),
            self.0.to_vec()
        )))
    }
}

impl std::str::FromStr for Window {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let v: Vec<f64> = s
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| format!("{s:?} is not A,B (two numbers)"))?;
        match v.as_slice() {
            [a, b] => Ok(Self([*a, *b])),
            _ => Err(format!("{s:?} is not A,B (two numbers)")),
        }
    }
}

impl std::fmt::Display for Window {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{},{}", self.0[0], self.0[1])
    }
}

/// A lattice size as given: one number N (a cube, or an N × N square in 2-D),
/// `NXxNZ` in 2-D, or `NXxNYxNZ`. On the command line `64`, `64x32`,
/// `64x64x32`; in JSON `64` or `[64, 64, 32]`. [`LatticeSize::resolve`] turns
/// it into the simulator's `[nx, ny, nz]` (`[nx, 1, nz]` in 2-D), the same for
/// every front end.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, JsonSchema)]
#[serde(into = "Vec<usize>")]
#[schemars(with = "SizeForm")]
pub struct LatticeSize(Vec<usize>);

/// The JSON forms of a [`LatticeSize`] (for its schema).
#[derive(JsonSchema)]
#[allow(dead_code)]
#[serde(untagged)]
enum SizeForm {
    /// One number N.
    One(#[schemars(range(min = 1, max = MAX_SIDE))] usize),
    /// One to three numbers.
    Many(#[schemars(length(min = 1, max = 3))] Vec<Side>),
}

impl<'de> serde::Deserialize<'de> for LatticeSize {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Sides;
        impl<'de> serde::de::Visitor<'de> for Sides {
            type Value = Vec<usize>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a lattice size: N or [NX, NY, NZ] (or [NX, NZ] in 2-D)")
            }
            fn visit_u64<E: serde::de::Error>(self, n: u64) -> std::result::Result<Vec<usize>, E> {
                usize::try_from(n).map(|n| vec![n]).map_err(E::custom)
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> std::result::Result<Vec<usize>, A::Error> {
                let mut v = Vec::new();
                while let Some(n) = seq.next_element::<usize>()? {
                    v.push(n);
                }
                Ok(v)
            }
        }
        let v = d.deserialize_any(Sides)?;
        LatticeSize::from_sides(v).map_err(serde::de::Error::custom)
    }
}

impl LatticeSize {
    fn from_sides(v: Vec<usize>) -> std::result::Result<Self, String> {
        if v.is_empty() || v.len() > 3 || v.contains(&0) {
            return Err(format!(
                "a lattice size is 1 to 3 sides, none zero (N, NXxNZ or NXxNYxNZ), got {v:?}"
            ));
        }
        Ok(Self(v))
    }
}

impl From<LatticeSize> for Vec<usize> {
    fn from(s: LatticeSize) -> Self {
        s.0
    }
}

impl LatticeSize {
    /// A size of these numbers (1 to 3 of them, none zero).
    ///
    /// # Errors
    /// [`EngineError::Invalid`] otherwise.
    pub fn new(sides: &[usize]) -> Result<Self> {
        Self::from_sides(sides.to_vec()).map_err(EngineError::Invalid)
    }

    /// An N × N × N lattice.
    pub fn cube(n: usize) -> Self {
        Self(vec![n; 3])
    }

    /// The sides as given.
    pub fn sides(&self) -> &[usize] {
        &self.0
    }

    /// The `[nx, ny, nz]` lattice of a `dim`-dimensional run: N gives N³
    /// (N × 1 × N in 2-D), NXxNZ a 2-D lattice NX × 1 × NZ, NXxNYxNZ itself.
    ///
    /// # Errors
    /// [`EngineError::Invalid`] when the count of numbers does not fit `dim`.
    pub fn resolve(&self, dim: usize) -> Result<[usize; 3]> {
        match (dim, self.0.as_slice()) {
            (3, [n]) => Ok([*n; 3]),
            (3, [x, y, z]) => Ok([*x, *y, *z]),
            (2, [n]) => Ok([*n, 1, *n]),
            (2, [x, z]) => Ok([*x, 1, *z]),
            (2, [x, 1, z]) => Ok([*x, 1, *z]),
            _ => Err(EngineError::Invalid(format!(
                "{} {self} does not fit {dim}-D: give N or {}",
                param("size"),
                if dim == 2 { "NXxNZ" } else { "NXxNYxNZ" }
            ))),
        }
    }
}

impl std::str::FromStr for LatticeSize {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let v: Vec<usize> = s
            .split(['x', 'X', '×'])
            .map(|x| x.trim().parse::<usize>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| format!("{s:?} is not N, NXxNZ or NXxNYxNZ"))?;
        Self::from_sides(v)
    }
}

impl std::fmt::Display for LatticeSize {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let parts: Vec<String> = self.0.iter().map(usize::to_string).collect();
        f.write_str(&parts.join("x"))
    }
}
