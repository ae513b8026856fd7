//! The part of a configuration the hydro stage reads, built once: the ship, the water column
//! and swell (the wind does not drive the wake model of spec 2.1), the grid, the time stepping,
//! the solver and the surface map's spacing. The stage runs on these alone, so a cache keyed by
//! their hash cannot drift from what it computes.

use crate::SurfaceMap;
use serde::Serialize;
use wakelab_core::config::{EnvironmentConfig, GridConfig, ShipConfig, SolverConfig, TimeConfig};
use wakelab_core::{WakelabConfig, WakelabError};

/// What [`simulate_surface_map`](crate::simulate_surface_map) reads of a configuration.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HydroInputs {
    pub ship: ShipConfig,
    /// The environment with the default wind in place of the configured one: the wind acts on
    /// the sea surface (stage 2), not on the wake's RANS model.
    pub environment: EnvironmentConfig,
    pub grid: GridConfig,
    pub time: TimeConfig,
    pub solver: SolverConfig,
    /// Along-track spacing of the surface map (m), `output.map_dx`.
    pub map_dx: f64,
}

impl HydroInputs {
    pub fn of(config: &WakelabConfig) -> Self {
        let mut environment = config.environment.clone();
        environment.wind = WakelabConfig::default().environment.wind;
        Self {
            ship: config.ship.clone(),
            environment,
            grid: config.grid.clone(),
            time: config.time.clone(),
            solver: config.solver.clone(),
            map_dx: config.output.map_dx,
        }
    }

    /// The inputs as JSON text, stable across runs: what a cache key hashes.
    pub fn key_text(&self) -> String {
        serde_json::to_string(self).expect("plain numbers and strings serialise")
    }

    /// A configuration that holds these inputs and the defaults elsewhere: the only one the
    /// stage sees.
    fn config(&self) -> WakelabConfig {
        let mut config = WakelabConfig {
            ship: self.ship.clone(),
            environment: self.environment.clone(),
            grid: self.grid.clone(),
            time: self.time.clone(),
            solver: self.solver.clone(),
            ..Default::default()
        };
        config.output.map_dx = self.map_dx;
        config
    }

    /// The wake's surface map (Eq. (2.24)) from these inputs alone, of a configuration that
    /// [`simulate_surface_map`](crate::simulate_surface_map) has validated whole (the defaults
    /// elsewhere, the scene's among them, need not fit these inputs).
    pub(crate) fn simulate(&self) -> Result<SurfaceMap, WakelabError> {
        let config = self.config();
        Ok(crate::keep_every_slice(&config)?.surface_map(&config, self.map_dx))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config(extra: &str) -> WakelabConfig {
        WakelabConfig::from_toml_str(extra, "test").unwrap()
    }

    /// The wind, the scene and the sensors are not the hydro stage's inputs; the ship, the swell
    /// (its Stokes drift drives the vortex force, Eq. (2.6)) and the grid are.
    #[test]
    fn the_inputs_hold_what_the_wake_model_reads() {
        let base = HydroInputs::of(&config("")).key_text();
        for other in [
            "[environment.wind]\nspeed = 12.0\ndirection = 40.0\n",
            "[scene]\nsize = 128\n",
            "[sar]\nlooks = 1\n",
        ] {
            assert_eq!(HydroInputs::of(&config(other)).key_text(), base, "{other}");
        }
        for other in [
            "[ship]\nspeed = 6.0\n",
            "[environment.swell]\namplitude = 0.5\n",
            "[output]\nmap_dx = 20.0\n",
        ] {
            assert_ne!(HydroInputs::of(&config(other)).key_text(), base, "{other}");
        }
    }
}
