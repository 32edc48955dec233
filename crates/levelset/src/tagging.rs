//! The initial offset surface by tagging (§5.2, Algorithm 1).
//!
//! Every node starts interior; the nodes on the faces of the grid (the bounding
//! box Γ₀ of the paper's Fig. 5) form the tagged boundary ∂Ω. A priority queue hands
//! out the boundary node farthest from the data; while that distance is at least ε
//! the node is tested and, if accepted, becomes exterior and its interior
//! neighbours (6-connected) join ∂Ω. The final ∂Ω approximates {d = ε}.
//!
//! Two acceptance rules:
//! * [`TagRule::Paper`] — Algorithm 1, line 4: accept only when no interior
//!   neighbour is farther from the data than the node itself. The front therefore
//!   descends the distance field and does not pass a neck (a saddle of d) into a
//!   pocket that widens again; a node refused once stays on the boundary. Ties
//!   (equal distances, e.g. the capped far field) count as "not farther".
//! * [`TagRule::Threshold`] — the ε rule only: accept every node with d ≥ ε. The
//!   exterior is then exactly the flood fill of {d ≥ ε} from the box, which the
//!   tests check against an independent breadth-first fill.
//!
//! With a capped distance (the closest-point method stops at the cap c) every node
//! beyond c looks equally far, so the paper's rule only sees necks narrower than 2c;
//! the pipeline sets c = ε + γ + 2h.
//!
//! Both rules are computed without the queue, with the same result (a test
//! checks both against Algorithm 1 run with a plain binary heap, refusals
//! included):
//! * The ε rule's exterior is the flood fill of {d ≥ ε} from the faces, filled
//!   plane-parallel by row spans (each plane from its seeds, then the planes
//!   above and below seeded from what it reached, until nothing changes).
//! * Under the paper's rule the queue pops in non-increasing distance: a node is
//!   accepted only when no non-exterior neighbour is farther, so everything it
//!   adds to ∂Ω is at most as far. When the pops reach a node's distance its
//!   farther neighbours are settled for good, so the node is reached iff it
//!   lies on a face or next to an exterior node, and accepted iff none of its
//!   farther neighbours is non-exterior. The far field (tied at the cap, always
//!   accepted) is the flood fill of {d ≥ cap}; the rest of the ε flood fill (a
//!   superset of the result) is sorted by decreasing distance once and decided in
//!   that order, equal distances together as a small flood. Unlike a heap, the
//!   sorted list says which nodes come next, so their scattered neighbourhoods
//!   are prefetched.

/// Which nodes Algorithm 1 accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TagRule {
    /// Algorithm 1 as published: the node must not have a farther interior neighbour.
    Paper,
    /// Only the ε rule: a flood fill of {d ≥ ε} from the box.
    Threshold,
}

#[cfg(feature = "reference")]
mod dense;
#[cfg(feature = "reference")]
pub use dense::{Tags, tag};
