//! The completeness check of the paper's algorithm, step 1 (Appendix 2: "verify
//! completeness of object"), and the explicit repair of what can be repaired —
//! both are the ones every surface method shares
//! ([`asperity_core::mesh_check`]), so a mesh `surface-ca` accepts is one
//! `subdiv` accepts.

pub use asperity_core::mesh_check::{RepairReport, repair_surface as repair};
use asperity_core::mesh_check::{SurfaceNeeds, check_triangles};
use asperity_core::{CoreError, TriMesh};

/// The step-1 check, the same as every surface method makes
/// ([`asperity_core::mesh_check`]): every triangle non-degenerate, every edge
/// shared by at most two triangles, the triangles around each vertex one fan,
/// shared edges used in opposite directions.
///
/// # Errors
/// [`CoreError::InvalidParameter`] describing the first problem and whether
/// `--repair` can fix it.
pub fn check(mesh: &TriMesh) -> Result<(), CoreError> {
    check_triangles(mesh, SurfaceNeeds::default()).map_err(|d| {
        let hint = if d.repairable() {
            "; ⟨repair⟩ fixes this"
        } else {
            " (this cannot be repaired automatically)"
        };
        CoreError::InvalidParameter {
            name: "mesh",
            reason: format!("{d}{hint}"),
        }
    })
}
