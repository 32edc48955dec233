//! Point sets: positions with optional colours, normals and named scalar attributes.

use crate::{Aabb, CoreError, tri_mesh::Attribute};

/// A set of 3-D points (e.g. occupied voxels from a growth simulation).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointSet {
    positions: Vec<[f64; 3]>,
    normals: Option<Vec<[f64; 3]>>,
    colors: Option<Vec<[u8; 4]>>,
    attributes: Vec<Attribute>,
}

impl PointSet {
    /// The points with `f` applied to every position and normal (a rotation or
    /// reflection, as [`crate::TriMesh::map_vectors`]).
    pub fn map_vectors(mut self, f: impl Fn([f64; 3]) -> [f64; 3]) -> Self {
        self.positions.iter_mut().for_each(|p| *p = f(*p));
        if let Some(n) = &mut self.normals {
            n.iter_mut().for_each(|v| *v = f(*v));
        }
        self
    }
    /// Points at `positions`, with no attributes.
    pub fn new(positions: Vec<[f64; 3]>) -> Self {
        Self {
            positions,
            ..Self::default()
        }
    }

    /// The first non-finite coordinate or attribute value, as an error.
    ///
    /// # Errors
    /// [`CoreError::NonFinite`].
    pub fn validate(&self) -> crate::Result<()> {
        crate::tri_mesh::check_finite_points("point", &self.positions)?;
        for a in &self.attributes {
            if let Some(k) = a.values.iter().position(|v| !v.is_finite()) {
                return Err(CoreError::NonFinite {
                    what: "attribute value",
                    index: k,
                    value: a.values[k],
                });
            }
        }
        Ok(())
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.positions.len()
    }
    /// Whether there are no points.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }
    /// Point positions.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }
    /// Per-point normals, if any.
    pub fn normals(&self) -> Option<&[[f64; 3]]> {
        self.normals.as_deref()
    }
    /// Per-point RGBA colours, if any.
    pub fn colors(&self) -> Option<&[[u8; 4]]> {
        self.colors.as_deref()
    }
    /// Named per-point scalars.
    pub fn attributes(&self) -> &[Attribute] {
        &self.attributes
    }
    /// The values of attribute `name`.
    pub fn attribute(&self, name: &str) -> Option<&[f64]> {
        self.attributes
            .iter()
            .find(|a| a.name == name)
            .map(|a| a.values.as_slice())
    }
    /// Bounding box, or `None` when empty.
    pub fn bounds(&self) -> Option<Aabb> {
        Aabb::from_points(&self.positions)
    }

    /// Sets per-point normals.
    ///
    /// # Errors
    /// [`CoreError::LengthMismatch`] unless there is one per point.
    pub fn set_normals(&mut self, normals: Vec<[f64; 3]>) -> crate::Result<()> {
        crate::tri_mesh::check_len("normals", normals.len(), self.len())?;
        self.normals = Some(normals);
        Ok(())
    }
    /// Sets per-point colours.
    ///
    /// # Errors
    /// [`CoreError::LengthMismatch`] unless there is one per point.
    pub fn set_colors(&mut self, colors: Vec<[u8; 4]>) -> crate::Result<()> {
        crate::tri_mesh::check_len("colors", colors.len(), self.len())?;
        self.colors = Some(colors);
        Ok(())
    }
    /// Adds (or replaces) a named per-point scalar.
    ///
    /// # Errors
    /// [`CoreError::LengthMismatch`] unless there is one value per point.
    pub fn add_attribute(&mut self, name: &str, values: Vec<f64>) -> crate::Result<()> {
        crate::tri_mesh::check_len(name, values.len(), self.len())?;
        self.attributes.retain(|a| a.name != name);
        self.attributes.push(Attribute {
            name: name.to_owned(),
            values,
        });
        Ok(())
    }
}
