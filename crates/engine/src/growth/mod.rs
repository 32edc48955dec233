//! Surface growth (kim-machiraju-thompson §4, §6 Fig. 8, §7): the simulators of
//! `asperity-growth` with the measurements of `asperity-analysis`.
//!
//! | Module | Job |
//! | --- | --- |
//! | [`deposition`] | RD, RDSR, BD on a flat periodic substrate; W(t), β, α |
//! | [`curved`] | RD, RDSR, BD on a sphere or a closed mesh |
//! | [`dla`] | DLA from a point, the plane, a ball, a mesh or an image; R_g, D |

pub mod curved;
pub mod deposition;
pub mod dla;
