//! `[ship]`: the ship and the empirical coefficients of its initial data plane (spec Tables
//! 2.1-2.2), with each value's allowed range.

use super::checks::{positive, range};
use crate::error::ConfigError;
use serde::{Deserialize, Serialize};

/// The ship and the empirical coefficients of its initial data plane (Tables 2.1-2.2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShipConfig {
    pub name: String,
    /// Length L (m).
    pub length: f64,
    /// Beam B (m).
    pub beam: f64,
    /// Draft D (m).
    pub draft: f64,
    /// Wetted surface area S (m^2).
    pub wetted_area: f64,
    /// Ship speed U_ship (m/s).
    pub speed: f64,
    /// Propeller diameter D_p (m).
    pub propeller_diameter: f64,
    /// Horizontal offset of each propeller axis from the centreline, y_p (m).
    pub propeller_offset: f64,
    /// Depth of the propeller axles, z_p (m, positive down).
    pub propeller_depth: f64,
    /// Horizontal offset of each rudder, y_r (m).
    pub rudder_offset: f64,
    /// Rudder mid-span depth z_r (m, positive down).
    pub rudder_depth: f64,
    /// Rudder thickness t_r (m).
    pub rudder_thickness: f64,
    /// Rudder chord c_r (m).
    pub rudder_chord: f64,
    /// Rudder planform area S_r (m^2).
    pub rudder_area: f64,
    /// Swirl number S~ (-).
    pub swirl_number: f64,
    /// Rudder drag coefficient C_dr (-).
    pub rudder_drag_coefficient: f64,
    /// Hull wave-making drag coefficient C_R (-).
    pub wave_drag_coefficient: f64,
    /// Table 2.2 coefficients.
    pub coefficients: IdpCoefficients,
}

/// The empirical IDP coefficients of Table 2.2.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IdpCoefficients {
    pub a1: f64,
    pub a2: f64,
    pub a3: f64,
    pub a4: f64,
    pub a: f64,
    pub a_p: f64,
    pub a_s1: f64,
    pub a_s2: f64,
    pub alpha_theta: f64,
    pub c_delta: f64,
}

impl ShipConfig {
    /// Check every value of `[ship]` against its allowed range; the error names the field.
    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        let s = self;
        positive("ship.length", s.length, 1.0, 500.0, "m")?;
        positive("ship.beam", s.beam, 0.5, 100.0, "m")?;
        positive("ship.draft", s.draft, 0.1, 40.0, "m")?;
        positive("ship.wetted_area", s.wetted_area, 1.0, 1.0e5, "m^2")?;
        positive("ship.speed", s.speed, 0.1, 30.0, "m/s")?;
        positive("ship.propeller_diameter", s.propeller_diameter, 0.1, 20.0, "m")?;
        range(
            "ship.propeller_offset",
            s.propeller_offset,
            0.0,
            s.beam,
            "m (0 to the beam)",
        )?;
        positive("ship.propeller_depth", s.propeller_depth, 0.1, 40.0, "m")?;
        range("ship.rudder_offset", s.rudder_offset, 0.0, s.beam, "m (0 to the beam)")?;
        positive("ship.rudder_depth", s.rudder_depth, 0.05, 40.0, "m")?;
        positive("ship.rudder_thickness", s.rudder_thickness, 0.01, 10.0, "m")?;
        positive("ship.rudder_chord", s.rudder_chord, 0.05, 50.0, "m")?;
        positive("ship.rudder_area", s.rudder_area, 0.01, 500.0, "m^2")?;
        range("ship.swirl_number", s.swirl_number, 0.0, 2.0, "")?;
        positive("ship.rudder_drag_coefficient", s.rudder_drag_coefficient, 1e-6, 2.0, "")?;
        range("ship.wave_drag_coefficient", s.wave_drag_coefficient, 0.0, 0.1, "")?;
        let c = &s.coefficients;
        for (name, v) in [
            ("a1", c.a1),
            ("a2", c.a2),
            ("a3", c.a3),
            ("a4", c.a4),
            ("a", c.a),
            ("a_p", c.a_p),
            ("a_s1", c.a_s1),
            ("a_s2", c.a_s2),
            ("alpha_theta", c.alpha_theta),
            ("c_delta", c.c_delta),
        ] {
            positive(&format!("ship.coefficients.{name}"), v, 1e-6, 100.0, "")?;
        }
        Ok(())
    }
}
