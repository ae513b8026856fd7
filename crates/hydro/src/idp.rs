//! The initial data plane (IDP) at x_IDP = 0.5 L behind the ship, spec Eqs. (2.26)-(2.62),
//! after Miner et al. (1988) and Somero et al. (2018).
//!
//! Coordinates here follow the spec: `y` across the track (m) and `d` the depth (m, positive
//! down, the spec's z in these equations). Each "+-" in the spec is the pair of port and
//! starboard contributions, summed.
//!
//! Where the spec is ambiguous:
//! - (2.55): the Gaussian covers both terms (erratum 8).
//! - (2.56): printed centred on the hull (y, z) like (2.28); a rudder's turbulence is centred on
//!   the rudder, so both terms are centred on (+-y_r, z_r), the rudder's own wake centre.
//! - (2.57): `C_d` is the rudder drag coefficient C_dr; B stays the beam, as in (2.29).
//! - (2.40), (2.41), (2.48), (2.52): U_0 is the ship speed.
//! - Swirl (2.51): the two propellers turn outboard (the DDG-5415's twin screws), so the swirl of
//!   the port screw is the mirror image of the starboard one.

use serde::Serialize;
use wakelab_core::config::{IdpCoefficients, ShipConfig};

/// Every derived scalar of the IDP model, named as in the spec.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct IdpScalars {
    /// Reynolds number U L / nu (Table 2.1).
    #[serde(rename = "Re")]
    pub reynolds: f64,
    /// Froude number U / sqrt(g L) (Table 2.1).
    #[serde(rename = "Fr")]
    pub froude: f64,
    /// Hull friction coefficient, Eq. (2.35).
    #[serde(rename = "C_f")]
    pub c_f: f64,
    /// Hull drag coefficient, Eq. (2.34).
    #[serde(rename = "C_D")]
    pub c_d: f64,
    /// Momentum thickness (m), Eq. (2.32).
    pub theta: f64,
    /// Virtual origin (m), Eq. (2.33).
    pub x_0: f64,
    /// IDP position behind the ship (m), Eq. (2.36).
    #[serde(rename = "x_IDP")]
    pub x_idp: f64,
    /// Hull wake half-width (m), Eq. (2.30).
    pub y_h: f64,
    /// Hull wake half-depth (m), Eq. (2.31).
    pub z_h: f64,
    /// Peak friction-wake velocity (m/s), Eq. (2.37).
    #[serde(rename = "U_f_max")]
    pub u_f_max: f64,
    /// Peak friction-wake TKE (m^2/s^2), Eq. (2.38).
    pub k_f_max: f64,
    /// Wave-making drag (N), Eq. (2.41).
    #[serde(rename = "R_wave")]
    pub r_wave: f64,
    /// Wave wake half-width (m), Eq. (2.42).
    pub y_hw: f64,
    /// Wave wake half-depth (m), Eq. (2.43).
    pub z_hw: f64,
    /// Peak wave-wake velocity (m/s), Eq. (2.40).
    #[serde(rename = "U_w_max")]
    pub u_w_max: f64,
    /// Thrust of each propeller (N), Eq. (2.48).
    #[serde(rename = "T")]
    pub thrust: f64,
    /// Propeller jet radius (m), Eq. (2.49).
    pub r_h: f64,
    /// Peak jet velocity (m/s), Eq. (2.47).
    #[serde(rename = "U_p_max")]
    pub u_p_max: f64,
    /// Peak jet TKE (m^2/s^2), Eq. (2.50).
    pub k_p_max: f64,
    /// Propeller torque (N m), Eq. (2.53).
    #[serde(rename = "Q")]
    pub torque: f64,
    /// Swirl half-radius (m), Eq. (2.54).
    pub r_sh: f64,
    /// Peak swirl velocity scale (m/s), Eq. (2.52).
    #[serde(rename = "V_s_max")]
    pub v_s_max: f64,
    /// Rudder wake constant, Eq. (2.62).
    pub a_r: f64,
    /// Rudder wake half-width (m), Eq. (2.60).
    pub y_rh: f64,
    /// Rudder wake half-height (m), Eq. (2.61).
    pub z_rh: f64,
    /// Peak rudder-wake velocity (m/s), Eq. (2.58).
    #[serde(rename = "U_r_max")]
    pub u_r_max: f64,
    /// Peak rudder-wake TKE (m^2/s^2), Eq. (2.59).
    pub k_r_max: f64,
}

/// The IDP model of one ship in one ocean.
#[derive(Debug, Clone)]
pub struct InitialDataPlane {
    pub ship: ShipConfig,
    pub scalars: IdpScalars,
}

/// IDP values at one point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct IdpPoint {
    /// Axial wake velocity U_0 of Eq. (2.26) (m/s): jet positive, deficits negative.
    pub u0: f64,
    /// Cross-track swirl velocity (m/s, +y).
    pub v: f64,
    /// Vertical swirl velocity (m/s, up).
    pub w: f64,
    /// TKE k_0 (m^2/s^2).
    pub k: f64,
    /// Dissipation rate eps_0 (m^2/s^3).
    pub eps: f64,
}

impl InitialDataPlane {
    /// Derive every scalar of the IDP from the ship, Eqs. (2.30)-(2.62).
    pub fn new(ship: &ShipConfig, kinematic_viscosity: f64, density: f64, gravity: f64) -> Self {
        let c: &IdpCoefficients = &ship.coefficients;
        let (u, l, b, s) = (ship.speed, ship.length, ship.beam, ship.wetted_area);
        let reynolds = u * l / kinematic_viscosity;
        let froude = u / (gravity * l).sqrt();
        // Eq. (2.35), ITTC 1957 friction line.
        let c_f = 0.075 / (reynolds.log10() - 2.0).powi(2);
        let c_d = c_f * s / (b * b); // (2.34)
        let theta = (c_d * b * b / 8.0).sqrt(); // (2.32)
        let x_0 = theta * (-(8.0f64).sqrt() * c.alpha_theta / (c.c_delta * c_d.sqrt())).powi(3); // (2.33)
        let x_idp = 0.5 * l; // (2.36)
        let y_h = theta * c.c_delta * ((x_idp - x_0) / theta).cbrt(); // (2.30)
        let z_h = 0.5 * y_h * (b / (2.0 * ship.draft)).powf(-2.0 / 3.0); // (2.31)
        let u_f_max = c.a * u * s * c_f / (std::f64::consts::PI * y_h * z_h); // (2.37)
        let k_f_max = (0.3 * u_f_max).powi(2); // (2.38)
        let r_wave = 0.5 * density * u * u * s * ship.wave_drag_coefficient; // (2.41)
        let y_hw = l / 20.0; // (2.42)
        let z_hw = ship.draft; // (2.43)
        let u_w_max = c.a * r_wave / (std::f64::consts::PI * density * u * y_hw * z_hw); // (2.40)
        let thrust = 0.5 * (0.5 * density * u * u * b * b * c_d + r_wave); // (2.48)
        let r_h = 0.086 * x_idp; // (2.49)
        let u_p_max = c.a * thrust / (std::f64::consts::PI * density * u * r_h * r_h); // (2.47)
        let k_p_max = (0.59 * u_p_max).powi(2); // (2.50)
        let torque = 0.5 * ship.swirl_number * thrust * ship.propeller_diameter; // (2.53)
        let r_sh = 0.095 * (x_idp * b).sqrt(); // (2.54)
        let v_s_max = c.a_s2 * torque / (std::f64::consts::PI * density * u * c.a_s1 * r_sh.powi(3)); // (2.52)
        let a_r = 0.23 * ship.rudder_drag_coefficient.sqrt(); // (2.62)
        let y_rh = a_r * (x_idp * ship.rudder_thickness).sqrt() + 0.5 * ship.rudder_thickness; // (2.60)
        let z_rh = ship.rudder_area / (2.0 * ship.rudder_chord); // (2.61)
        let u_r_max =
            a_r * u * ship.rudder_area * ship.rudder_drag_coefficient / (2.0 * std::f64::consts::PI * y_rh * z_rh); // (2.58)
        let k_r_max = u_r_max * u_r_max; // (2.59)
        Self {
            ship: ship.clone(),
            scalars: IdpScalars {
                reynolds,
                froude,
                c_f,
                c_d,
                theta,
                x_0,
                x_idp,
                y_h,
                z_h,
                u_f_max,
                k_f_max,
                r_wave,
                y_hw,
                z_hw,
                u_w_max,
                thrust,
                r_h,
                u_p_max,
                k_p_max,
                torque,
                r_sh,
                v_s_max,
                a_r,
                y_rh,
                z_rh,
                u_r_max,
                k_r_max,
            },
        }
    }

    /// Every IDP field at cross-track position `y` and depth `d` (both m; d positive down).
    pub fn at(&self, y: f64, d: f64) -> IdpPoint {
        let sc = &self.scalars;
        let sh = &self.ship;
        let c = &sh.coefficients;
        let b = sh.beam;
        let sides = [1.0, -1.0];
        let sq = |x: f64| x * x;

        // Hull friction wake, (2.27)-(2.29).
        let u_f: f64 = sides
            .iter()
            .map(|s| sc.u_f_max * (-3.5 * c.a * (sq((y + s * 0.3 * b) / sc.y_h) + sq(d / sc.z_h))).exp())
            .sum();
        let rf2 = sq(y / sc.y_h) + sq(d / sc.z_h);
        let k_f = (sc.k_f_max * (c.a1 * (-c.a2 * rf2).exp() - c.a3 * (-c.a4 * rf2).exp())).max(0.0);
        let eps_f = (24.0 * sc.u_f_max / (sc.c_d * b * b * sh.speed)).sqrt() * k_f.powf(1.5);

        // Wave-making wake, (2.39).
        let u_w: f64 = sides
            .iter()
            .map(|s| sc.u_w_max * (-6.0 * c.a * (sq((y + s * 0.6 * b) / sc.y_hw) + sq(d / sc.z_hw))).exp())
            .sum();

        // Propeller jets and swirl, (2.44)-(2.46), (2.51).
        let (mut u_p, mut k_p, mut v, mut w) = (0.0, 0.0, 0.0, 0.0);
        for s in sides {
            let centre_y = s * sh.propeller_offset;
            let ry = y - centre_y;
            let rz = -(d - sh.propeller_depth); // upward offset from the axle
            let r = (ry * ry + rz * rz).sqrt();
            u_p += sc.u_p_max * (-2.0 * c.a_p * sq(r / sc.r_h)).exp();
            k_p += sc.k_p_max * (-c.a * sq(r / sc.r_h)).exp();
            let vs = sc.v_s_max * c.a_s1 * (r / sc.r_sh) * (-c.a_s2 * sq(r / sc.r_sh)).exp();
            if r > 0.0 {
                // Outboard-turning screws: at the top of the disc the flow moves outboard (sign s).
                v += s * vs * rz / r;
                w += -s * vs * ry / r;
            }
        }
        let eps_p = 12f64.sqrt() / b * k_p.powf(1.5);

        // Rudders, (2.55)-(2.57) with erratum 8.
        let (mut u_r, mut k_r) = (0.0, 0.0);
        for s in sides {
            let r2 = sq((y - s * sh.rudder_offset) / sc.y_rh) + sq((d - sh.rudder_depth) / sc.z_rh);
            u_r += sc.u_r_max * (-c.a * r2).exp();
            k_r += (sc.k_r_max * (c.a1 * (-c.a2 * r2).exp() - c.a3 * (-c.a4 * r2).exp())).max(0.0);
        }
        let eps_r = (24.0 * sc.u_r_max / (sh.rudder_drag_coefficient * b * b * sh.speed)).sqrt() * k_r.powf(1.5);

        IdpPoint {
            u0: u_p - (u_f + u_r + u_w), // (2.26)
            v,
            w,
            k: k_p + k_f + k_r,
            eps: eps_p + eps_f + eps_r,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wakelab_core::WakelabConfig;

    fn ddg() -> InitialDataPlane {
        let c = WakelabConfig::default();
        InitialDataPlane::new(&c.ship, 1e-6, 1025.0, 9.81)
    }

    fn close(a: f64, b: f64, rel: f64) -> bool {
        ((a - b) / b).abs() < rel
    }

    /// Table 2.1's Re and Fr and the spec README's independent sanity figures.
    #[test]
    fn scalars_match_table_2_1_and_spec_sanity_figures() {
        let s = ddg().scalars;
        let checks = [
            ("Re", s.reynolds, 9.94e8, 5e-3),
            ("Fr", s.froude, 0.188, 5e-3),
            ("C_f", s.c_f, 1.532e-3, 1e-3),
            ("C_D", s.c_d, 1.265e-2, 1e-3),
            ("theta", s.theta, 0.7515, 1e-3),
            ("y_h", s.y_h, 9.667, 1e-3),
            ("z_h", s.z_h, 3.634, 1e-3),
            ("U_f,max", s.u_f_max, 0.745, 1e-3),
            ("U_p,max", s.u_p_max, 0.405, 2e-3),
            ("r_h", s.r_h, 6.106, 1e-3),
            ("T", s.thrust, 1.308e5, 1e-3),
            ("R_wave", s.r_wave, 1.481e5, 1e-3),
        ];
        for (name, got, want, rel) in checks {
            assert!(close(got, want, rel), "{name}: got {got}, want {want}");
        }
    }

    #[test]
    fn wake_is_symmetric_and_swirl_is_mirrored() {
        let idp = ddg();
        let a = idp.at(3.0, 5.0);
        let b = idp.at(-3.0, 5.0);
        assert!((a.u0 - b.u0).abs() < 1e-12 && (a.k - b.k).abs() < 1e-15);
        assert!((a.v + b.v).abs() < 1e-12 && (a.w - b.w).abs() < 1e-12);
        // On the port propeller axis the jet dominates the deficits.
        let p = idp.at(4.2, 5.11);
        assert!(p.u0 > 0.0 && p.k > 0.0 && p.eps > 0.0);
        // Far away everything vanishes.
        let far = idp.at(200.0, 100.0);
        assert!(far.u0.abs() < 1e-12 && far.k < 1e-12);
    }
}
