//! The wakelab configuration: TOML with an embedded default for every value.
//!
//! A configuration is built in three layers: the embedded default, the preset named by a
//! top-level `preset` key (`quick` or `paper`, which set the grid and time tables), then the
//! user's file, merged table by table. Unknown keys are errors, and [`WakelabConfig::validate`]
//! checks every number against its allowed range before any work starts.

use crate::error::{ConfigError, WakelabError};
use serde::{Deserialize, Serialize};
use std::path::Path;

mod checks;
mod environment;
mod numerics;
mod output;
mod scene;
mod sensors;
mod ship;
mod surface;

pub use environment::*;
pub use numerics::*;
pub use output::*;
pub use scene::*;
pub use sensors::*;
pub use ship::*;
pub use surface::*;

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

/// The embedded default configuration, as TOML (the `quick` preset).
pub const DEFAULT_TOML: &str = include_str!("../../../../configs/scene/default.toml");

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

const QUICK_PRESET: &str = include_str!("../../../../configs/scene/quick.toml");

const PAPER_PRESET: &str = include_str!("../../../../configs/scene/paper.toml");

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

    /// This configuration with a wind speed and a radar incidence from the command line where
    /// they are given, validated (a bad value is refused naming its field).
    pub fn with_wind_and_incidence(mut self, wind: Option<f64>, incidence: Option<f64>) -> Result<Self, ConfigError> {
        if let Some(speed) = wind {
            self.environment.wind.speed = speed;
        }
        if let Some(angle) = incidence {
            self.platform.incidence = angle;
        }
        self.validate()?;
        Ok(self)
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

impl WakelabConfig {
    /// Check every value against its allowed range, section by section (each section's ranges
    /// sit beside its fields); the error names the field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.ship.validate()?;
        self.environment.validate(self.grid.depth)?;
        self.grid.validate(&self.ship)?;
        self.time.validate()?;
        self.solver.validate()?;
        self.sea.validate()?;
        self.scene.validate(self.sea.window, self.wake_end())?;
        self.slicks.validate()?;
        self.kelvin.validate()?;
        self.platform.validate()?;
        self.sar.validate()?;
        self.ir.validate()?;
        self.output.validate()
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
