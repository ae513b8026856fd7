//! The wakelab configuration: TOML with an embedded default for every value.
//!
//! A configuration is built in three layers: the embedded default, the preset named by a
//! top-level `preset` key (`quick` or `paper`, which set the grid and time tables), then the
//! user's file, merged table by table. Unknown keys are errors, and [`WakelabConfig::validate`]
//! checks every number against its allowed range before any work starts.

use crate::error::{ConfigError, WakelabError};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The complete, effective configuration of a wakelab run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WakelabConfig {
    /// The preset the grid and time tables started from (`quick` or `paper`).
    pub preset: Preset,
    /// Seed of every random draw in the run.
    pub seed: u64,
    pub ship: ShipConfig,
    pub environment: EnvironmentConfig,
    pub grid: GridConfig,
    pub time: TimeConfig,
    pub solver: SolverConfig,
    pub sea: SeaConfig,
    pub scene: SceneConfig,
    /// Natural slicks on the scene.
    pub slicks: SlickConfig,
    /// The ship's Kelvin wake and its own return in wake scenes.
    pub kelvin: KelvinConfig,
    pub platform: PlatformConfig,
    pub sar: SarConfig,
    pub ir: IrConfig,
    pub output: OutputConfig,
}

/// Grid and time presets (spec 2.1.2 for `paper`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Preset {
    /// A coarse grid that runs in seconds.
    #[default]
    Quick,
    /// The spec's grid: 2000 m x 300 m core of 4001 x 201 cells plus 500 m beaches of 101 cells.
    Paper,
}

impl std::str::FromStr for Preset {
    type Err = ConfigError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "quick" => Ok(Self::Quick),
            "paper" => Ok(Self::Paper),
            other => Err(ConfigError::new("preset", other, "one of `quick`, `paper`")),
        }
    }
}

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

/// The ocean the ship sails through.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentConfig {
    /// Latitude (degrees north) for TEOS-10 pressure and gravity.
    pub latitude: f64,
    /// Longitude (degrees east, -180..360) for TEOS-10.
    pub longitude: f64,
    /// Gravitational acceleration g (m/s^2).
    pub gravity: f64,
    /// Molecular kinematic viscosity nu (m^2/s), Table 2.1.
    pub kinematic_viscosity: f64,
    /// Reference density rho_0 (kg/m^3), Table 2.1.
    pub reference_density: f64,
    /// Background in-situ temperature T_b(z) (deg C).
    pub temperature: Profile,
    /// Background practical salinity S_b(z) (PSU).
    pub salinity: Profile,
    pub swell: SwellConfig,
    pub wind: WindConfig,
    /// Ambient (background) turbulence kinetic energy (m^2/s^2).
    pub ambient_tke: f64,
    /// Ambient dissipation rate (m^2/s^3).
    pub ambient_dissipation: f64,
}

/// Shape of a background profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProfileKind {
    /// `surface + depth_gradient * depth` everywhere.
    Linear,
    /// Uniform `surface` down to `mixed_layer_depth`, then the linear gradient below (Fig. 3.3).
    MixedLayer,
}

/// A background profile f_b(z) (Eq. (2.7)), constant in time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Profile {
    pub kind: ProfileKind,
    /// Value at the surface.
    pub surface: f64,
    /// Change per metre of depth (negative: decreasing downward).
    pub depth_gradient: f64,
    /// Depth of the mixed layer (m); used by `mixed_layer` only.
    pub mixed_layer_depth: f64,
}

impl Profile {
    /// Value at depth `depth` (m, positive down).
    pub fn at_depth(&self, depth: f64) -> f64 {
        let below = match self.kind {
            ProfileKind::Linear => depth,
            ProfileKind::MixedLayer => (depth - self.mixed_layer_depth).max(0.0),
        };
        self.surface + self.depth_gradient * below
    }
}

/// Swell direction relative to the ship's track: a name or degrees. Read by hand rather than as
/// an untagged enum, whose error ("did not match any variant") names no allowed value.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(untagged)]
pub enum SwellDirection {
    /// `calm`, `following`, `head` or `beam`.
    Named(NamedDirection),
    /// Direction of propagation in degrees from the ship's heading, counter-clockwise seen from
    /// above (0 = following, 90 = towards port, the +y side, 180 = head).
    Degrees(f64),
}

impl<'de> Deserialize<'de> for SwellDirection {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        const ALLOWED: &str = "calm, following, head, beam, or degrees from the heading (a number)";
        impl serde::de::Visitor<'_> for Visitor {
            type Value = SwellDirection;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "a swell direction: {ALLOWED}")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<SwellDirection, E> {
                let named = match v {
                    "calm" => NamedDirection::Calm,
                    "following" => NamedDirection::Following,
                    "head" => NamedDirection::Head,
                    "beam" => NamedDirection::Beam,
                    _ => {
                        return Err(E::custom(format!(
                            "unknown swell direction \"{v}\"; allowed: {ALLOWED}"
                        )))
                    }
                };
                Ok(SwellDirection::Named(named))
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<SwellDirection, E> {
                Ok(SwellDirection::Degrees(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<SwellDirection, E> {
                Ok(SwellDirection::Degrees(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<SwellDirection, E> {
                Ok(SwellDirection::Degrees(v as f64))
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// The named swell directions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NamedDirection {
    Calm,
    Following,
    Head,
    Beam,
}

/// The swell whose Stokes drift (Eq. (2.1)) drives the vortex force (Eq. (2.6)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SwellConfig {
    /// Amplitude a_s (m).
    pub amplitude: f64,
    /// Wavelength lambda (m).
    pub wavelength: f64,
    /// Direction of propagation relative to the track.
    pub direction: SwellDirection,
}

impl SwellConfig {
    /// Propagation angle from the ship's heading (radians), or `None` for a calm sea.
    pub fn angle(&self) -> Option<f64> {
        match self.direction {
            SwellDirection::Named(NamedDirection::Calm) => None,
            _ if self.amplitude == 0.0 => None,
            SwellDirection::Named(NamedDirection::Following) => Some(0.0),
            SwellDirection::Named(NamedDirection::Beam) => Some(std::f64::consts::FRAC_PI_2),
            SwellDirection::Named(NamedDirection::Head) => Some(std::f64::consts::PI),
            SwellDirection::Degrees(d) => Some(d.to_radians()),
        }
    }
}

/// The wind over the scene (used by the surface stage).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindConfig {
    /// Wind speed at 10 m (m/s).
    pub speed: f64,
    /// Direction the wind blows towards, degrees from the ship's heading.
    pub direction: f64,
    /// Relative standard deviation of the wind speed over the scene (0: uniform); its low-wind
    /// patches are dark in SAR like slicks.
    pub variability: f64,
    /// Correlation length of the wind speed's variation over the scene (m).
    pub gust_length: f64,
}

/// Natural (biogenic) slicks on the open sea: patches and filaments of surface film, in wake and
/// no-wake scenes alike.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlickConfig {
    /// Expected fraction of the scene under slicks (0: none).
    pub coverage: f64,
    /// Correlation length of the slick field across its filaments (m).
    pub length: f64,
    /// Length over width of the filaments, which run along the wind.
    pub elongation: f64,
    /// Reference dilational elasticity of a slick's film (N/m), in place of the open sea's
    /// `sea.film_elasticity`.
    pub elasticity: f64,
}

/// The ship's Kelvin wave pattern (linear thin-ship theory, Michell 1898) and the ship's own
/// radar and infrared return, in wake scenes (a no-wake scene has no ship).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KelvinConfig {
    /// Add the Kelvin wave field and the ship's return; false leaves scenes as without them.
    pub enabled: bool,
    /// The hull's form, scaled to `ship.length`, `ship.beam` and `ship.draft`.
    pub hull: HullForm,
    /// Radar cross section of the ship (m^2) in every band; unset: Skolnik's empirical
    /// sigma = 52 f^(1/2) D^(3/2) (f in MHz, D the displacement in kilotonnes) per band.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ship_rcs: Option<f64>,
    /// Temperature of the hull's sides above the sea surface's (K), for its infrared signature.
    pub hull_temperature_excess: f64,
    /// Emissivity of the hull's paint in the infrared.
    pub hull_emissivity: f64,
}

/// Hull forms of the thin-ship source distribution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HullForm {
    /// Wigley's parabolic hull, y = (B/2) (1 - (2x/L)^2) (1 - (z/T)^2) (Wigley 1934).
    Wigley,
}

impl HullForm {
    /// The form's name as the configuration writes it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Wigley => "wigley",
        }
    }
}

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

/// Background wave spectrum models (spec 2.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SpectrumModel {
    /// Pierson-Moskowitz (Eq. (2.71)) for the long waves joined to the Lyzenga-Bennett power law
    /// B k^-c (Eq. (2.70)) for the short waves.
    PiersonMoskowitz,
    /// Elfouhaily et al. (1997) unified directional spectrum.
    Elfouhaily,
}

/// The ocean surface stage: wave spectrum, surface film and the random sea surface (spec 2.2-2.3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeaConfig {
    pub spectrum: SpectrumModel,
    /// Elfouhaily inverse wave age Omega_c (0.84: fully developed sea).
    pub inverse_wave_age: f64,
    /// Lyzenga-Bennett exponent c of the short-wave power law B k^-c of the 2D spectrum.
    pub short_wave_exponent: f64,
    /// Wavenumber where the power law takes over from Pierson-Moskowitz, in multiples of k_p.
    pub short_wave_join: f64,
    /// Relative spectral width (in k) of the swell component.
    pub swell_width: f64,
    /// Directional spread of the swell (degrees, standard deviation).
    pub swell_spread: f64,
    /// Dilational elasticity of the surface film at the reference concentration Gamma = 1 (N/m).
    pub film_elasticity: f64,
    /// Surface tension of clean sea water tau_w (N/m).
    pub surface_tension: f64,
    /// Side of the sampling window of the random surface (pixels, even; Eqs. (2.72)-(2.76)).
    pub window: usize,
}

/// The scene imaged by the sensors: a square of `size` x `size` pixels on the sea surface.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneConfig {
    /// Pixel spacing (m).
    pub pixel_spacing: f64,
    /// Pixels per side.
    pub size: usize,
    /// Distance behind the stern of the scene centre (m).
    pub along_track: f64,
    /// Cross-track offset of the scene centre from the ship's track (m, positive to port).
    pub cross_track: f64,
    /// The ship's course in the image, degrees clockwise from up (a compass heading on a
    /// north-up image); 270 runs the ship to the left with its wake trailing to the right.
    pub heading: f64,
    /// Further wakes in the scene (`[[scene.other_wakes]]`): the same ship's wake placed again,
    /// as if other ships of its kind had passed; the scene's own placement above is the first.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub other_wakes: Vec<WakePlacement>,
}

/// Where a wake lies in the scene: the scene centre's distance behind that ship's stern (m), its
/// offset to port of that ship's track (m) and the ship's course in the image (degrees clockwise
/// from up), as in [`SceneConfig`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WakePlacement {
    pub along_track: f64,
    pub cross_track: f64,
    pub heading: f64,
}

impl SceneConfig {
    /// The placement of every wake in the scene, the scene's own first.
    pub fn wake_placements(&self) -> Vec<WakePlacement> {
        let own = WakePlacement {
            along_track: self.along_track,
            cross_track: self.cross_track,
            heading: self.heading,
        };
        std::iter::once(own).chain(self.other_wakes.iter().cloned()).collect()
    }

    /// This scene with its own wake placed at `placement` and no other.
    pub fn with_wake_at(&self, placement: &WakePlacement) -> SceneConfig {
        SceneConfig {
            along_track: placement.along_track,
            cross_track: placement.cross_track,
            heading: placement.heading,
            other_wakes: Vec::new(),
            ..self.clone()
        }
    }
}

/// Viewing geometry of the imaging platform.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlatformConfig {
    /// Incidence angle at the scene centre (degrees).
    pub incidence: f64,
    /// Horizontal direction the sensor looks in, degrees counter-clockwise from the ship's heading
    /// (90: looking towards port, across the track).
    pub look_direction: f64,
}

/// SAR polarisation (transmit and receive alike).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Polarisation {
    Vv,
    Hh,
}

/// `vv` or `hh`, in either case.
impl std::str::FromStr for Polarisation {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "vv" => Ok(Self::Vv),
            "hh" => Ok(Self::Hh),
            _ => Err(format!("{s}: must be vv or hh")),
        }
    }
}

/// The SAR sensor (spec 3.1). With `looks = 0`, `noise_floor = false` and
/// `velocity_bunching = false` it is the spec's perfect SAR.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SarConfig {
    pub polarisation: Polarisation,
    /// Number of independent looks of the speckle; 0 for none.
    pub looks: u32,
    /// Resolution (m): the width of the impulse response, over which speckle and thermal noise
    /// are correlated; 0 for the pixel spacing.
    pub resolution: f64,
    /// Add thermal noise at the band's noise-equivalent sigma zero.
    pub noise_floor: bool,
    /// One noise-equivalent sigma zero for every band (dB); unset: each band's own below.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nesz: Option<f64>,
    /// S-band NESZ (dB).
    pub nesz_s: f64,
    /// C-band NESZ (dB).
    pub nesz_c: f64,
    /// X-band NESZ (dB).
    pub nesz_x: f64,
    /// Displace scatterers in azimuth by their line-of-sight orbital velocity times R/V.
    pub velocity_bunching: bool,
    /// Slant range over platform speed R/V (s).
    pub range_to_velocity: f64,
}

impl SarConfig {
    /// The noise-equivalent sigma zero of `band` (dB).
    pub fn nesz_db(&self, band: crate::units::RadarBand) -> f64 {
        use crate::units::RadarBand::*;
        self.nesz.unwrap_or(match band {
            S => self.nesz_s,
            C => self.nesz_c,
            X => self.nesz_x,
        })
    }

    /// The resolution in pixels of `pixel_spacing` (1 when the resolution is the pixel).
    pub fn resolution_pixels(&self, pixel_spacing: f64) -> f64 {
        if self.resolution > 0.0 {
            self.resolution / pixel_spacing
        } else {
            1.0
        }
    }
}

/// The infrared sensor (spec 3.2, Eq. (3.5) and Algorithm 1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IrConfig {
    /// Sun elevation above the horizon (degrees).
    pub sun_elevation: f64,
    /// Direction of the sun, degrees counter-clockwise from the ship's heading.
    pub sun_azimuth: f64,
    /// Brightness temperature of the sun's photosphere (K).
    pub sun_temperature: f64,
    /// Henyey-Greenstein asymmetry G of the sun's scattering lobe (Eq. (3.19)).
    pub sun_asymmetry: f64,
    /// Sky brightness temperature at the zenith (K), Eq. (3.20).
    pub sky_zenith_temperature: f64,
    /// Sky brightness temperature at the horizon (K), Eq. (3.20).
    pub sky_horizon_temperature: f64,
    /// Add the imager's noise, of standard deviation `netd`, to the brightness temperature.
    pub noise: bool,
    /// Noise-equivalent temperature difference (K).
    pub netd: f64,
    /// Full width at half maximum of the imager's point-spread function (m); 0: the pixel.
    pub resolution: f64,
}

/// Where and what the run writes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputConfig {
    /// Run directory.
    pub dir: String,
    /// Along-track spacing of the surface (x, y) map (m).
    pub map_dx: f64,
    /// Write NetCDF files.
    pub netcdf: bool,
    /// Write PNG pictures.
    pub pictures: bool,
}

/// The embedded default configuration, as TOML (the `quick` preset).
pub const DEFAULT_TOML: &str = include_str!("../../../configs/scene/default.toml");

impl Preset {
    /// The grid and time tables of this preset, as TOML.
    pub fn overlay(&self) -> toml::Table {
        let text = match self {
            Preset::Quick => QUICK_PRESET,
            Preset::Paper => PAPER_PRESET,
        };
        text.parse::<toml::Table>().expect("embedded preset is valid TOML")
    }
}

const QUICK_PRESET: &str = include_str!("../../../configs/scene/quick.toml");

const PAPER_PRESET: &str = include_str!("../../../configs/scene/paper.toml");

/// Merge `over` into `base`, table by table (values of `over` win).
fn merge_tables(base: &mut toml::Table, over: toml::Table) {
    for (key, value) in over {
        match (base.get_mut(&key), value) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => merge_tables(b, o),
            (_, v) => {
                base.insert(key, v);
            }
        }
    }
}

impl Default for WakelabConfig {
    fn default() -> Self {
        Self::from_toml_str("", "<embedded default>").expect("embedded default is valid")
    }
}

impl WakelabConfig {
    /// How far behind the stern the simulated wake reaches (m): the hull's aft half plus the
    /// ship's run over the simulated time (the 3D wake of x = U t, spec 2.1).
    pub fn wake_end(&self) -> f64 {
        0.5 * self.ship.length + self.ship.speed * self.time.duration
    }

    /// The embedded default with the given preset's grid and time.
    pub fn with_preset(preset: Preset) -> Self {
        Self::from_toml_str(&format!("preset = \"{}\"", preset.name()), "<preset>").expect("embedded presets are valid")
    }

    /// Build the effective configuration from a user's TOML text, layered over the default and
    /// the preset it names. Unknown keys and out-of-range values are errors.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Self, WakelabError> {
        Self::from_toml_str_with_preset(text, origin, None)
    }

    /// The configuration of the TOML file at `path` (`None`: the embedded default), with
    /// `preset` (from the command line) replacing the file's, validated.
    pub fn from_file_with_preset(path: Option<&std::path::Path>, preset: Option<Preset>) -> Result<Self, WakelabError> {
        let (text, origin) = match path {
            Some(p) => (
                std::fs::read_to_string(p).map_err(|e| WakelabError::io(p, e))?,
                p.display().to_string(),
            ),
            None => (String::new(), "<embedded default>".to_string()),
        };
        Self::from_toml_str_with_preset(&text, &origin, preset)
    }

    /// As [`Self::from_toml_str`], with `preset` (from the command line) replacing the file's.
    pub fn from_toml_str_with_preset(text: &str, origin: &str, preset: Option<Preset>) -> Result<Self, WakelabError> {
        let config = Self::from_toml_str_unvalidated(text, origin, preset)?;
        config.validate()?;
        Ok(config)
    }

    /// Layer and parse like [`Self::from_toml_str_with_preset`] (unknown keys are still errors)
    /// without range checks: for templates, such as a study's base, whose every derived
    /// configuration is validated on its own.
    pub fn from_toml_str_unvalidated(text: &str, origin: &str, preset: Option<Preset>) -> Result<Self, WakelabError> {
        let parse_err = |message: String| WakelabError::Parse {
            path: origin.to_string(),
            message,
        };
        let mut user: toml::Table = text.parse().map_err(|e: toml::de::Error| parse_err(e.to_string()))?;
        if let Some(p) = preset {
            user.insert("preset".into(), toml::Value::String(p.name().into()));
        }
        let preset = match user.get("preset") {
            None => Preset::Quick,
            Some(toml::Value::String(s)) => s.parse()?,
            Some(other) => return Err(ConfigError::new("preset", other, "one of `quick`, `paper`").into()),
        };
        let mut table: toml::Table = DEFAULT_TOML.parse().expect("embedded default is valid TOML");
        merge_tables(&mut table, preset.overlay());
        merge_tables(&mut table, user);
        let config: WakelabConfig = toml::Value::Table(table)
            .try_into()
            .map_err(|e: toml::de::Error| parse_err(e.to_string()))?;
        Ok(config)
    }

    /// Read a configuration file (see [`Self::from_toml_str`]).
    pub fn from_file(path: &Path) -> Result<Self, WakelabError> {
        let text = std::fs::read_to_string(path).map_err(|e| WakelabError::io(path, e))?;
        Self::from_toml_str(&text, &path.display().to_string())
    }

    /// A stable identifier of the run's configuration: FNV-1a (64 bit) of its effective TOML.
    pub fn scene_id(&self) -> String {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in self.to_toml_string().bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        format!("{h:016x}")
    }

    /// The effective configuration as TOML, which reads back to the same configuration.
    pub fn to_toml_string(&self) -> String {
        toml::to_string_pretty(self).expect("configuration serialises")
    }
}

impl Preset {
    pub fn name(&self) -> &'static str {
        match self {
            Preset::Quick => "quick",
            Preset::Paper => "paper",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_is_the_ddg5415_of_table_2_1() {
        let c = WakelabConfig::default();
        assert_eq!(c.ship.length, 142.0);
        assert_eq!(c.ship.beam, 18.9);
        assert_eq!(c.ship.wetted_area, 2949.5);
        assert_eq!(c.ship.speed, 7.0);
        assert_eq!(c.ship.coefficients.c_delta, 1.14);
        assert_eq!(c.preset, Preset::Quick);
    }

    #[test]
    fn paper_preset_has_the_spec_grid() {
        let c = WakelabConfig::with_preset(Preset::Paper);
        assert_eq!(
            (c.grid.core_cells, c.grid.depth_cells, c.grid.beach_cells),
            (4001, 201, 101)
        );
        assert_eq!(
            (c.grid.core_width, c.grid.depth, c.grid.beach_width),
            (2000.0, 300.0, 500.0)
        );
        assert_eq!(c.time.duration, 3600.0);
    }

    #[test]
    fn a_swell_direction_is_a_name_or_degrees_and_a_bad_name_lists_the_allowed() {
        let read = |d: &str| WakelabConfig::from_toml_str(&format!("[environment.swell]\ndirection = {d}\n"), "t");
        let direction = |d: &str| read(d).unwrap().environment.swell.direction;
        assert_eq!(direction("\"head\""), SwellDirection::Named(NamedDirection::Head));
        assert_eq!(direction("45"), SwellDirection::Degrees(45.0));
        assert_eq!(direction("-22.5"), SwellDirection::Degrees(-22.5));
        let e = read("\"opposing\"").unwrap_err().to_string();
        assert!(
            e.contains("\"opposing\"") && e.contains("calm, following, head, beam"),
            "{e}"
        );
    }

    #[test]
    fn shown_config_reads_back_identically() {
        let c = WakelabConfig::with_preset(Preset::Paper);
        let back = WakelabConfig::from_toml_str(&c.to_toml_string(), "shown").unwrap();
        assert_eq!(c, back);
    }

    #[test]
    fn user_values_override_the_preset() {
        let c = WakelabConfig::from_toml_str("preset = \"paper\"\n[grid]\ncore_cells = 1001\n", "t").unwrap();
        assert_eq!(c.grid.core_cells, 1001);
        assert_eq!(c.grid.depth_cells, 201);
    }

    #[test]
    fn unknown_key_is_an_error_naming_it() {
        let err = WakelabConfig::from_toml_str("[ship]\nsped = 3.0\n", "t").unwrap_err();
        assert!(err.to_string().contains("sped"), "{err}");
    }

    #[test]
    fn out_of_range_value_names_field_and_range() {
        let err = WakelabConfig::from_toml_str("[ship]\nspeed = -3.0\n", "t").unwrap_err();
        let msg = err.to_string();
        assert!(
            msg.contains("ship.speed") && msg.contains("-3") && msg.contains("[0.1, 30]"),
            "{msg}"
        );
    }

    #[test]
    fn swell_direction_accepts_names_and_degrees() {
        let c = WakelabConfig::from_toml_str("[environment.swell]\ndirection = \"head\"\n", "t").unwrap();
        assert_eq!(c.environment.swell.angle(), Some(std::f64::consts::PI));
        let c = WakelabConfig::from_toml_str("[environment.swell]\ndirection = 45.0\n", "t").unwrap();
        assert!((c.environment.swell.angle().unwrap() - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
        let c = WakelabConfig::from_toml_str("[environment.swell]\ndirection = \"calm\"\n", "t").unwrap();
        assert_eq!(c.environment.swell.angle(), None);
        assert!(WakelabConfig::from_toml_str("[environment.swell]\ndirection = \"sideways\"\n", "t").is_err());
    }

    #[test]
    fn too_steep_swell_is_refused() {
        let err =
            WakelabConfig::from_toml_str("[environment.swell]\namplitude = 8.0\nwavelength = 50.0\n", "t").unwrap_err();
        assert!(err.to_string().contains("environment.swell.amplitude"), "{err}");
    }

    #[test]
    fn mixed_layer_profile_is_uniform_above_the_layer() {
        let p = Profile {
            kind: ProfileKind::MixedLayer,
            surface: 20.0,
            depth_gradient: -0.05,
            mixed_layer_depth: 30.0,
        };
        assert_eq!(p.at_depth(10.0), 20.0);
        assert!((p.at_depth(50.0) - 19.0).abs() < 1e-12);
    }
}
