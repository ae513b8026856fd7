//! The physical constants the surface models share (one place, so that the film, short-wave and
//! spectrum models cannot disagree on them).

/// Sea-water density used for capillarity (kg/m^3).
pub const RHO_WATER: f64 = 1025.0;
/// Molecular kinematic viscosity of sea water (m^2/s), Table 2.1.
pub const NU: f64 = 1e-6;
/// Density of air (kg/m^3).
pub const RHO_AIR: f64 = 1.225;
/// Von Karman's constant.
pub const KARMAN: f64 = 0.4;
