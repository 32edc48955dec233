//! Exported details (velho-perlin §2's multiresolution representation, written
//! out): the detail offsets of every level in their local frames, with the base
//! they belong to, so they can be re-applied to an edited base — the paper's
//! "edit the coarse level, keep the fine detail".
//!
//! The file is JSON: `{"format": "asperity-subdiv-details-1", "base_vertices",
//! "base_faces", "levels", "details": [[[t₁, t₂, n], …], …]}` (per level, per
//! vertex; an empty level has no details).

use serde::{Deserialize, Serialize};

use crate::catmull_clark::Creased;
use crate::multires::Details;

/// The format tag of the current version.
pub const FORMAT: &str = "asperity-subdiv-details-1";

/// Details with enough of their base to check they fit the base they are
/// applied to.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DetailFile {
    /// [`FORMAT`].
    pub format: String,
    /// Vertices of the base.
    pub base_vertices: usize,
    /// Faces of the base.
    pub base_faces: usize,
    /// Subdivision levels.
    pub levels: usize,
    /// Per level, per vertex (t₁, t₂, n) components; empty = none.
    pub details: Details,
}

impl DetailFile {
    /// The details of a surface of `levels` levels on `base`.
    pub fn new(base: &Creased, levels: usize, details: Details) -> Self {
        Self {
            format: FORMAT.into(),
            base_vertices: base.mesh.n_vertices(),
            base_faces: base.mesh.n_faces(),
            levels,
            details,
        }
    }

    /// The file as JSON text.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("details serialise")
    }

    /// Reads the JSON text of a details file.
    ///
    /// # Errors
    /// A message when the text is not a details file or of another version.
    pub fn from_json(text: &str) -> Result<Self, String> {
        let f: DetailFile = serde_json::from_str(text)
            .map_err(|e| format!("not an asperity details file ({e})"))?;
        if f.format != FORMAT {
            return Err(format!("unknown details format {:?}", f.format));
        }
        Ok(f)
    }

    /// Checks that the details belong to a base like `base`.
    ///
    /// # Errors
    /// A message with both sizes.
    pub fn check_base(&self, base: &Creased) -> Result<(), String> {
        let (v, f) = (base.mesh.n_vertices(), base.mesh.n_faces());
        if self.base_vertices == v && self.base_faces == f {
            Ok(())
        } else {
            Err(format!(
                "the details belong to a base of {} vertices and {} faces; this base has {v} and {f}",
                self.base_vertices, self.base_faces
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_refusals() {
        let cube = Creased::smooth(asperity_core::shapes::cube_cage());
        let f = DetailFile::new(&cube, 2, vec![vec![[0.1, 0.2, 0.3]; 26], Vec::new()]);
        let back = DetailFile::from_json(&f.to_json()).unwrap();
        assert_eq!(back, f);
        assert!(back.check_base(&cube).is_ok());
        let sphere = Creased::smooth(crate::base::quad_sphere(2));
        assert!(back.check_base(&sphere).unwrap_err().contains("8 vertices"));
        let other = f.to_json().replace(FORMAT, "x-2");
        assert!(DetailFile::from_json(&other).unwrap_err().contains("x-2"));
        assert!(DetailFile::from_json("{}").is_err());
    }
}
