//! Axis-aligned bounding boxes.

use serde::{Deserialize, Serialize};

/// An axis-aligned box `[min, max]` in 3-D.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Aabb {
    /// Lower corner.
    pub min: [f64; 3],
    /// Upper corner.
    pub max: [f64; 3],
}

impl Aabb {
    /// The box around `points`, or `None` if there are none.
    pub fn from_points(points: &[[f64; 3]]) -> Option<Self> {
        let first = *points.first()?;
        let mut b = Aabb {
            min: first,
            max: first,
        };
        for p in &points[1..] {
            b.include(*p);
        }
        Some(b)
    }

    /// Grows the box to contain `p`.
    pub fn include(&mut self, p: [f64; 3]) {
        for (a, v) in p.into_iter().enumerate() {
            self.min[a] = self.min[a].min(v);
            self.max[a] = self.max[a].max(v);
        }
    }

    /// Edge lengths.
    pub fn extent(&self) -> [f64; 3] {
        [0, 1, 2].map(|a| self.max[a] - self.min[a])
    }

    /// Centre point.
    pub fn center(&self) -> [f64; 3] {
        [0, 1, 2].map(|a| 0.5 * (self.max[a] + self.min[a]))
    }

    /// Length of the diagonal.
    pub fn diagonal(&self) -> f64 {
        let e = self.extent();
        (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt()
    }

    /// The box grown by `pad` on every side.
    pub fn padded(&self, pad: f64) -> Self {
        Aabb {
            min: self.min.map(|v| v - pad),
            max: self.max.map(|v| v + pad),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_of_points() {
        let b = Aabb::from_points(&[[0.0, 1.0, 2.0], [-1.0, 3.0, 2.5]]).expect("non-empty");
        assert_eq!(b.min, [-1.0, 1.0, 2.0]);
        assert_eq!(b.max, [0.0, 3.0, 2.5]);
        assert_eq!(b.extent(), [1.0, 2.0, 0.5]);
        assert!((b.diagonal() - (1.0f64 + 4.0 + 0.25).sqrt()).abs() < 1e-15);
        assert!(Aabb::from_points(&[]).is_none());
    }
}
