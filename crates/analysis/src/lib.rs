//! Roughness analysis of height fields, point sets and meshes.
//!
//! **Status: planned** (issue "Roughness analysis"). Will provide ISO 25178 areal
//! parameters, PSDs and Hurst exponents, interface-width fits (α, β) for
//! [kim-machiraju-thompson] §4.1, cluster fractal dimensions, and mesh curvature.
//!
//! [kim-machiraju-thompson]: ../shared/papers/kim-machiraju-thompson_modeling-rough-surfaces.txt
