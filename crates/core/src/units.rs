//! Physical constants used across stages, with their source.

/// Standard gravity (m/s^2) used by the spec's hydrodynamics (Table 2.1 context, Eq. 2.1).
pub const STANDARD_GRAVITY: f64 = 9.81;

/// Degrees to radians.
pub fn deg_to_rad(deg: f64) -> f64 {
    deg.to_radians()
}
