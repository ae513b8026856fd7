//! `[grid]`, `[time]` and `[solver]`: the hydrodynamic model's grid, time stepping and solver
//! settings (spec 2.1.2), with each value's allowed range.

use super::checks::{count, positive, range};
use super::ship::ShipConfig;
use crate::error::ConfigError;
use serde::{Deserialize, Serialize};

/// The cross-wake grid (spec 2.1.2): a uniform core and stretched damping beaches on each side.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridConfig {
    /// Width of the uniform core (m).
    pub core_width: f64,
    /// Depth of the domain (m).
    pub depth: f64,
    /// Cells across the core.
    pub core_cells: usize,
    /// Cells over the depth.
    pub depth_cells: usize,
    /// Width of each damping beach (m); 0 for none.
    pub beach_width: f64,
    /// Cells in each beach.
    pub beach_cells: usize,
}

/// Simulated time and output times.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeConfig {
    /// Simulated wake age (s); the wake is U_ship * duration long (Eq. (2.24)).
    pub duration: f64,
    /// Courant number of the adaptive time step.
    pub cfl: f64,
    /// Largest time step (s).
    pub max_dt: f64,
    /// Interval between saved surface slices (s), from which the (x, y) map is built.
    pub surface_interval: f64,
    /// Interval between saved full cross-sections (s).
    pub output_interval: f64,
}

/// Lateral boundary of the 2D+t domain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LateralBoundary {
    /// Outlets behind the damping beaches (spec 2.1.2): pressure fixed, zero-gradient velocity.
    Outlet,
    /// Free-slip, no-flux walls (for closed-box tests).
    Wall,
}

/// Numerical and model options of the hydrodynamic solver.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverConfig {
    /// Somero (2021) near-surface anisotropy correction, Eqs. (2.15)-(2.21); off in the paper.
    pub somero_anisotropy: bool,
    /// Rate of the beach damping at the outer edge (1/s); grows quadratically from the core.
    pub beach_damping: f64,
    pub lateral_boundary: LateralBoundary,
    /// Upper limit on the eddy viscosity nu_t (m^2/s).
    pub max_eddy_viscosity: f64,
}

impl GridConfig {
    /// Check every value of `[grid]` (the ship sets its least depth and width) against its allowed range; the error names the field.
    pub(super) fn validate(&self, ship: &ShipConfig) -> Result<(), ConfigError> {
        let (g, s) = (self, ship);
        positive("grid.core_width", g.core_width, 10.0, 20_000.0, "m")?;
        positive("grid.depth", g.depth, 5.0, 2000.0, "m")?;
        count("grid.core_cells", g.core_cells, 8, 20_001)?;
        count("grid.depth_cells", g.depth_cells, 4, 2001)?;
        range("grid.beach_width", g.beach_width, 0.0, 20_000.0, "m")?;
        if g.beach_width > 0.0 {
            count("grid.beach_cells", g.beach_cells, 2, 2001)?;
        } else if g.beach_cells != 0 {
            return Err(ConfigError::new(
                "grid.beach_cells",
                g.beach_cells,
                "0 when grid.beach_width is 0",
            ));
        }
        let deepest = s.propeller_depth + s.propeller_diameter;
        if g.depth < 2.0 * deepest {
            return Err(ConfigError::new(
                "grid.depth",
                g.depth,
                format!(
                    "at least {:.1} m (twice the propeller depth plus diameter)",
                    2.0 * deepest
                ),
            ));
        }
        if g.core_width < 4.0 * s.beam {
            return Err(ConfigError::new(
                "grid.core_width",
                g.core_width,
                format!("at least {:.1} m (four beams)", 4.0 * s.beam),
            ));
        }
        Ok(())
    }
}

impl TimeConfig {
    /// Check every value of `[time]` against its allowed range; the error names the field.
    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        let t = self;
        positive("time.duration", t.duration, 1.0, 86_400.0, "s")?;
        positive("time.cfl", t.cfl, 0.01, 0.9, "")?;
        positive("time.max_dt", t.max_dt, 1e-3, 600.0, "s")?;
        positive(
            "time.surface_interval",
            t.surface_interval,
            1e-2,
            t.duration,
            "s (up to time.duration)",
        )?;
        positive(
            "time.output_interval",
            t.output_interval,
            1e-2,
            t.duration,
            "s (up to time.duration)",
        )?;
        Ok(())
    }
}

impl SolverConfig {
    /// Check every value of `[solver]` against its allowed range; the error names the field.
    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        let so = self;
        range("solver.beach_damping", so.beach_damping, 0.0, 10.0, "1/s")?;
        positive("solver.max_eddy_viscosity", so.max_eddy_viscosity, 1e-4, 100.0, "m^2/s")?;
        Ok(())
    }
}
