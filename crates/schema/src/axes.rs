//! The study axes, declared once (spec chapter 4 opening, Fig. 4.3): each axis's name, type,
//! what it describes and the configuration field it sets. The study file's `[axes]` table, a
//! scene's combination of values, the manifest's columns, the configuration of each scene and
//! the held-out axes all follow from the one list in [`study_axes!`]'s invocation below.

use serde::{Deserialize, Serialize};
use wakelab_core::config::{Polarisation, ProfileKind, SwellDirection, WakelabConfig};
use wakelab_core::ConfigError;

/// What an axis describes, which decides where it is used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisKind {
    /// The sea and the ship: part of a scene's environment (what a grouped split keeps on one
    /// side) and an axis a held-out test can group by.
    Environment,
    /// Where the wake lies relative to the sensor: an axis a held-out test can group by, not
    /// part of the environment.
    Geometry,
    /// How the image is made (polarisation, pixels): neither.
    Imaging,
}

/// One study axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Axis {
    /// The key in `[axes]`, the manifest's column and the combination's field.
    pub name: &'static str,
    /// The configuration field it sets, as the configuration's errors name it.
    pub config_field: &'static str,
    pub kind: AxisKind,
}

impl Axis {
    /// Whether a held-out robustness test can group scenes by this axis.
    pub fn can_hold_out(self) -> bool {
        self.kind != AxisKind::Imaging
    }
}

/// How the axes combine into scenes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Combine {
    /// Every combination of the axes' values.
    Product,
    /// The i-th value of each axis (axes of one value repeat it).
    Zip,
}

/// Index lists into the axes' value lists, one per combination.
fn combination_indices(lengths: &[usize], names: &[&str], combine: Combine) -> Result<Vec<Vec<usize>>, ConfigError> {
    match combine {
        Combine::Product => Ok(lengths.iter().fold(vec![vec![]], |out, &n| {
            out.into_iter()
                .flat_map(|prefix: Vec<usize>| {
                    (0..n).map(move |i| {
                        let mut p = prefix.clone();
                        p.push(i);
                        p
                    })
                })
                .collect()
        })),
        Combine::Zip => {
            let n = lengths.iter().copied().filter(|&l| l > 1).max().unwrap_or(1);
            if let Some(bad) = lengths.iter().position(|&l| l != 1 && l != n) {
                return Err(ConfigError::new(
                    format!("axes.{}", names[bad]),
                    format!("{} values", lengths[bad]),
                    format!("with combine = \"zip\" every axis has 1 or {n} values"),
                ));
            }
            Ok((0..n)
                .map(|i| lengths.iter().map(|&l| if l == 1 { 0 } else { i }).collect())
                .collect())
        }
    }
}

/// A type an axis can take. Numeric (f64) axes may also be given as an evenly spaced range.
pub trait AxisValue: Sized {
    /// The value of a range's point, for axes that take ranges.
    fn from_range_point(_v: f64) -> Option<Self> {
        None
    }
}

impl AxisValue for f64 {
    fn from_range_point(v: f64) -> Option<Self> {
        Some(v)
    }
}
impl AxisValue for u32 {}
impl AxisValue for usize {}
impl AxisValue for SwellDirection {}
impl AxisValue for ProfileKind {}
impl AxisValue for Polarisation {}

/// An evenly spaced range of axis values, both ends included: `{ from = 0.0, to = 315.0, count = 8 }`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
struct AxisRange {
    from: f64,
    to: f64,
    count: usize,
}

impl AxisRange {
    fn values<T: AxisValue>(self) -> Result<Vec<T>, String> {
        if !(self.from.is_finite() && self.to.is_finite() && (1..=10_000).contains(&self.count)) {
            return Err(format!(
                "a range needs finite `from` and `to` and a `count` in [1, 10000], got {self:?}"
            ));
        }
        let step = if self.count > 1 {
            (self.to - self.from) / (self.count - 1) as f64
        } else {
            0.0
        };
        (0..self.count)
            .map(|i| {
                T::from_range_point(self.from + step * i as f64)
                    .ok_or_else(|| "only a numeric axis takes a range { from, to, count }; give a list".to_string())
            })
            .collect()
    }
}

/// An axis of the study file: a list of values, or a range `{ from, to, count }`.
fn list_or_range<'de, D, T>(deserializer: D) -> Result<Option<Vec<T>>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: AxisValue + Deserialize<'de>,
{
    use serde::de::{value::MapAccessDeserializer, value::SeqAccessDeserializer, Error, MapAccess, SeqAccess, Visitor};
    struct Values<T>(std::marker::PhantomData<T>);
    impl<'de, T: AxisValue + Deserialize<'de>> Visitor<'de> for Values<T> {
        type Value = Vec<T>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a list of values, or a range { from, to, count }")
        }
        fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Vec<T>, A::Error> {
            Vec::<T>::deserialize(SeqAccessDeserializer::new(seq))
        }
        fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Vec<T>, A::Error> {
            AxisRange::deserialize(MapAccessDeserializer::new(map))?
                .values()
                .map_err(A::Error::custom)
        }
    }
    deserializer.deserialize_any(Values(std::marker::PhantomData)).map(Some)
}

/// Declares the axes: `name: Type = Kind, "config.field" => config.field;` for each.
macro_rules! study_axes {
    ($( $(#[doc = $doc:literal])* $name:ident : $ty:ty = $kind:ident, $field:literal => $($path:ident).+ ; )*) => {
        /// One combination of axis values (a wake/no-wake pair before the seed).
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        pub struct Combination {
            $( $(#[doc = $doc])* pub $name: $ty, )*
        }

        /// The `[axes]` table: every axis a list of values; a missing axis keeps the base
        /// configuration's value.
        #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct Axes {
            $(
                $(#[doc = $doc])*
                #[serde(default, deserialize_with = "list_or_range", skip_serializing_if = "Option::is_none")]
                pub $name: Option<Vec<$ty>>,
            )*
        }

        /// Every axis, in the manifest's column order.
        pub const AXES: &[Axis] = &[
            $( Axis { name: stringify!($name), config_field: $field, kind: AxisKind::$kind }, )*
        ];

        impl Combination {
            /// The axis values a configuration has.
            pub fn from_config(config: &WakelabConfig) -> Self {
                Self { $( $name: config.$($path).+.clone(), )* }
            }

            /// Set the axis values in a configuration.
            pub fn apply_to(&self, config: &mut WakelabConfig) {
                $( config.$($path).+ = self.$name.clone(); )*
            }
        }

        impl Axes {
            /// Every combination of the axes' values, in a fixed order (the first axis varies
            /// slowest); an axis the table leaves out takes `base`'s value.
            pub fn combinations(&self, base: &Combination, combine: Combine) -> Result<Vec<Combination>, ConfigError> {
                $(
                    let $name: Vec<$ty> = match &self.$name {
                        Some(v) if v.is_empty() => {
                            return Err(ConfigError::new(concat!("axes.", stringify!($name)), "[]", "a non-empty list"))
                        }
                        Some(v) => v.clone(),
                        None => vec![base.$name.clone()],
                    };
                )*
                let lengths = [$( $name.len() ),*];
                let names = [$( stringify!($name) ),*];
                Ok(combination_indices(&lengths, &names, combine)?
                    .into_iter()
                    .map(|idx| {
                        let mut next = idx.into_iter();
                        Combination { $( $name: $name[next.next().expect("one index per axis")].clone(), )* }
                    })
                    .collect())
            }
        }
    };
}

study_axes! {
    wind_speed: f64 = Environment, "environment.wind.speed" => environment.wind.speed;
    wind_direction: f64 = Environment, "environment.wind.direction" => environment.wind.direction;
    /// Relative standard deviation of the wind speed over the scene (low-wind patches).
    wind_variability: f64 = Environment, "environment.wind.variability" => environment.wind.variability;
    swell_amplitude: f64 = Environment, "environment.swell.amplitude" => environment.swell.amplitude;
    swell_wavelength: f64 = Environment, "environment.swell.wavelength" => environment.swell.wavelength;
    swell_direction: SwellDirection = Environment, "environment.swell.direction" => environment.swell.direction;
    /// "linear" or "mixed_layer".
    stratification: ProfileKind = Environment, "environment.temperature.kind" => environment.temperature.kind;
    /// Expected fraction of the scene under natural slicks.
    slick_coverage: f64 = Environment, "slicks.coverage" => slicks.coverage;
    ship_speed: f64 = Environment, "ship.speed" => ship.speed;
    /// Distance of the scene centre behind the stern (m).
    along_track: f64 = Geometry, "scene.along_track" => scene.along_track;
    /// Offset of the scene centre to port of the track (m).
    cross_track: f64 = Geometry, "scene.cross_track" => scene.cross_track;
    /// The ship's course in the image, degrees clockwise from up.
    heading: f64 = Geometry, "scene.heading" => scene.heading;
    incidence: f64 = Geometry, "platform.incidence" => platform.incidence;
    look_direction: f64 = Imaging, "platform.look_direction" => platform.look_direction;
    /// Slant range over the platform's velocity, R/V (s): how far a moving target's return is
    /// displaced in azimuth (spaceborne SARs: 40-130 s).
    range_to_velocity: f64 = Imaging, "sar.range_to_velocity" => sar.range_to_velocity;
    polarisation: Polarisation = Imaging, "sar.polarisation" => sar.polarisation;
    /// Looks of the SAR's speckle (0: the perfect SAR).
    looks: u32 = Imaging, "sar.looks" => sar.looks;
    pixel_spacing: f64 = Imaging, "scene.pixel_spacing" => scene.pixel_spacing;
    image_size: usize = Imaging, "scene.size" => scene.size;
}

/// The axis that sets a configuration field, if any.
pub fn axis_of_config_field(field: &str) -> Option<Axis> {
    AXES.iter().copied().find(|a| a.config_field == field)
}

/// Names of the axes a held-out robustness test can group scenes by.
pub fn held_out_axes() -> Vec<&'static str> {
    AXES.iter().filter(|a| a.can_hold_out()).map(|a| a.name).collect()
}

/// Names of the geometry axes a held-out geometry test can bin (continuous ones: the ship's
/// heading, the wake's age behind the stern, its offset, the incidence).
pub fn held_out_geometry_axes() -> Vec<&'static str> {
    AXES.iter()
        .filter(|a| a.kind == AxisKind::Geometry)
        .map(|a| a.name)
        .collect()
}

impl Combination {
    /// The value of axis `name` as the manifest's CSV writes it: numbers as Rust prints them,
    /// enumerations by their names in the study file.
    pub fn value_text(&self, name: &str) -> Option<String> {
        let value = serde_json::to_value(self).ok()?.get(name)?.clone();
        Some(match value {
            serde_json::Value::String(s) => s,
            serde_json::Value::Number(n) => match n.as_u64() {
                Some(u) => u.to_string(),
                None => n.as_f64().map_or_else(|| n.to_string(), |f| f.to_string()),
            },
            other => other.to_string(),
        })
    }

    /// Whether axis `name` takes continuous values (a float), which a study can draw at random.
    pub fn is_continuous(&self, name: &str) -> bool {
        serde_json::to_value(self)
            .ok()
            .and_then(|v| v.get(name).map(|x| x.is_f64()))
            .unwrap_or(false)
    }

    /// The combination with continuous axis `name` set to `value`.
    pub fn with_value(&self, name: &str, value: f64) -> Option<Self> {
        if !self.is_continuous(name) {
            return None;
        }
        let mut v = serde_json::to_value(self).ok()?;
        v[name] = serde_json::json!(value);
        serde_json::from_value(v).ok()
    }

    /// The environment, for grouped splits: every environment axis, by name.
    pub fn environment_key(&self) -> String {
        AXES.iter()
            .filter(|a| a.kind == AxisKind::Environment)
            .map(|a| format!("{}={}", a.name, self.value_text(a.name).unwrap_or_default()))
            .collect::<Vec<_>>()
            .join(" ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_axis_round_trips_through_a_configuration() {
        let config = WakelabConfig::default();
        let mut c = Combination::from_config(&config);
        c.wind_speed = 7.5;
        c.image_size = 96;
        c.stratification = ProfileKind::MixedLayer;
        let mut changed = config.clone();
        c.apply_to(&mut changed);
        assert_eq!(changed.environment.wind.speed, 7.5);
        assert_eq!(changed.scene.size, 96);
        assert_eq!(Combination::from_config(&changed), c);
        // the manifest names enumerations as the study file does
        assert_eq!(c.value_text("stratification").as_deref(), Some("mixed_layer"));
        assert_eq!(c.value_text("wind_speed").as_deref(), Some("7.5"));
        assert_eq!(c.value_text("image_size").as_deref(), Some("96"));
    }

    /// Each numeric axis's `config_field` is the name the configuration's own validation gives
    /// when that axis is out of range, so a study's error can be mapped back to its axis.
    #[test]
    fn every_numeric_axis_names_the_field_the_validation_reports() {
        let config = WakelabConfig::default();
        let base = serde_json::to_value(Combination::from_config(&config)).unwrap();
        let mut checked = 0;
        for axis in AXES {
            if !base[axis.name].is_number() {
                continue;
            }
            let mut bad = base.clone();
            bad[axis.name] = serde_json::json!(1_000_000_000u64);
            let mut c = config.clone();
            serde_json::from_value::<Combination>(bad).unwrap().apply_to(&mut c);
            let err = c.validate().expect_err(axis.name);
            assert_eq!(err.field, axis.config_field, "axis {}", axis.name);
            checked += 1;
        }
        assert_eq!(
            checked, 16,
            "every axis but swell direction, stratification and polarisation"
        );
    }

    /// A numeric axis takes a list or an evenly spaced range with both ends; other axes a list.
    #[test]
    fn an_axis_is_a_list_or_a_range() {
        let axes: Axes =
            serde_json::from_str(r#"{"heading": {"from": 0.0, "to": 315.0, "count": 8}, "wind_speed": [5.0, 8.0]}"#)
                .unwrap();
        assert_eq!(
            axes.heading.unwrap(),
            vec![0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0]
        );
        assert_eq!(axes.wind_speed.unwrap(), vec![5.0, 8.0]);
        let err = serde_json::from_str::<Axes>(r#"{"polarisation": {"from": 0.0, "to": 1.0, "count": 2}}"#)
            .unwrap_err()
            .to_string();
        assert!(err.contains("only a numeric axis takes a range"), "{err}");
        let err = serde_json::from_str::<Axes>(r#"{"heading": {"from": 0.0, "to": 1.0, "count": 0}}"#)
            .unwrap_err()
            .to_string();
        assert!(err.contains("count"), "{err}");
        let base = Combination::from_config(&WakelabConfig::default());
        assert!(base.is_continuous("heading") && !base.is_continuous("image_size"));
        assert_eq!(base.with_value("heading", 12.5).unwrap().heading, 12.5);
        assert!(base.with_value("polarisation", 1.0).is_none());
    }

    #[test]
    fn product_and_zip_enumerate_as_documented() {
        let base = Combination::from_config(&WakelabConfig::default());
        let axes = Axes {
            wind_speed: Some(vec![3.0, 5.0]),
            incidence: Some(vec![20.0, 30.0, 40.0]),
            ..Axes::default()
        };
        let product = axes.combinations(&base, Combine::Product).unwrap();
        assert_eq!(product.len(), 6);
        assert_eq!((product[1].wind_speed, product[1].incidence), (3.0, 30.0));
        assert_eq!(product[5].look_direction, base.look_direction);
        let err = axes.combinations(&base, Combine::Zip).unwrap_err();
        assert_eq!(err.field, "axes.wind_speed");
        let zip = Axes {
            wind_speed: Some(vec![3.0, 5.0, 7.0]),
            ..axes.clone()
        }
        .combinations(&base, Combine::Zip)
        .unwrap();
        assert_eq!(zip.len(), 3);
        assert_eq!((zip[2].wind_speed, zip[2].incidence), (7.0, 40.0));
        let empty = Axes {
            polarisation: Some(vec![]),
            ..Axes::default()
        };
        assert_eq!(
            empty.combinations(&base, Combine::Product).unwrap_err().field,
            "axes.polarisation"
        );
    }
}
