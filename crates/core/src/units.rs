//! Physical constants used across stages, with their source.

/// Standard gravity (m/s^2) used by the spec's hydrodynamics (Table 2.1 context, Eq. (2.1)).
pub const STANDARD_GRAVITY: f64 = 9.81;

/// Degrees to radians.
pub fn deg_to_rad(deg: f64) -> f64 {
    deg.to_radians()
}

/// Speed of light in vacuum (m/s).
pub const SPEED_OF_LIGHT: f64 = 299_792_458.0;

/// The SAR bands of spec Table 3.1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
pub enum RadarBand {
    S,
    C,
    X,
}

impl RadarBand {
    pub const ALL: [RadarBand; 3] = [RadarBand::S, RadarBand::C, RadarBand::X];

    /// Centre frequency (Hz), Table 3.1: S 3.1 GHz, C 5.3 GHz, X 9.6 GHz.
    pub fn frequency(&self) -> f64 {
        match self {
            RadarBand::S => 3.1e9,
            RadarBand::C => 5.3e9,
            RadarBand::X => 9.6e9,
        }
    }

    /// Radar wavenumber k_0 = 2 pi f / c (rad/m).
    pub fn wavenumber(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.frequency() / SPEED_OF_LIGHT
    }

    /// Bragg wavenumber 2 k_0 sin(theta) of the resonant sea waves at incidence `theta_deg`.
    pub fn bragg_wavenumber(&self, theta_deg: f64) -> f64 {
        2.0 * self.wavenumber() * theta_deg.to_radians().sin()
    }

    pub fn name(&self) -> &'static str {
        match self {
            RadarBand::S => "S",
            RadarBand::C => "C",
            RadarBand::X => "X",
        }
    }
}

/// A band by its name, in either case: `S`, `C` or `X`.
impl std::str::FromStr for RadarBand {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|b| b.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| format!("{s}: must be S, C or X"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bragg_wavelength_is_half_the_radar_wavelength_over_sin_theta() {
        // C band 5.3 GHz: lambda = 5.66 cm; at 30 degrees the Bragg wavelength is lambda / (2 sin 30) = 5.66 cm
        let lambda = SPEED_OF_LIGHT / 5.3e9;
        let kb = RadarBand::C.bragg_wavenumber(30.0);
        assert!((2.0 * std::f64::consts::PI / kb - lambda).abs() < 1e-12);
    }

    #[test]
    fn bands_parse_by_name_in_either_case() {
        assert_eq!("c".parse::<RadarBand>(), Ok(RadarBand::C));
        assert_eq!("X".parse::<RadarBand>(), Ok(RadarBand::X));
        assert!("L".parse::<RadarBand>().unwrap_err().contains("S, C or X"));
    }
}
