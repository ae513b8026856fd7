//! The scale of a radar image's values, and their conversion to linear sigma0 with the checks
//! that keep a wrong scale from scoring silently: a "linear" image whose values are largely
//! negative, or whose sea is brighter than any sea's backscatter, is refused with what it looks
//! like; so is a "dB" image whose values are those of linear sigma0 or of an 8-bit display. The
//! few slightly negative pixels that noise subtraction leaves are raised to a positive floor and
//! counted.

use ndarray::Array2;
use rayon::prelude::*;
use serde::Serialize;
use wakelab_core::ConfigError;

/// The floor for slightly negative linear sigma0 where the product gives no noise-equivalent
/// sigma0 (-50 dB, below every spaceborne SAR's noise floor).
pub const MIN_SIGMA0: f64 = 1e-5;

/// The amplitude a zero digital number is raised to: half a quantisation step.
const DN_FLOOR: f32 = 0.5;

/// Brightest median linear sigma0 accepted as sea (+10 dB; the ocean's sigma0 stays below
/// +5 dB at the steepest incidence, CMOD5.N's range).
const MAX_SEA_MEDIAN: f64 = 10.0;

/// sigma0 after noise removal, or where that left it at or below zero the noise-equivalent
/// sigma0 there (`nesz`; [`MIN_SIGMA0`] where that is not positive either), and whether it was
/// floored.
pub fn floored_at_noise(sigma0: f64, nesz: f64) -> (f32, bool) {
    if sigma0 > 0.0 {
        (sigma0 as f32, false)
    } else {
        ((if nesz > 0.0 { nesz } else { MIN_SIGMA0 }) as f32, true)
    }
}

/// The scale of a radar image's values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum InputScale {
    /// sigma0 as a power ratio.
    Linear,
    /// 10 log10 sigma0.
    Db,
    /// sqrt sigma0.
    Amplitude,
    /// A display-stretched image (8-bit grey levels): read as dB up to an unknown gain and
    /// offset, which the detector's normalisation cancels; its probabilities are uncalibrated.
    Display,
    /// Digital numbers of amplitude, not calibrated: sqrt sigma0 times a gain the file does not
    /// give (a Sentinel-1 GRD measurement TIFF read alone, sigma0 = DN^2 / A^2 with A in the
    /// product's calibration annotation, ESA S1-RS-MDA-52-7441 section 7.4; other vendors'
    /// amplitude products alike). Read as amplitude: the gain is one offset in dB, which the
    /// detector's normalisation (a window's median of dB) and the ship and wake searches (in dB
    /// against their own backgrounds) cancel. The image's sigma0 in dB is not given.
    Dn,
}

impl InputScale {
    pub const ALL: [InputScale; 5] = [
        InputScale::Linear,
        InputScale::Db,
        InputScale::Amplitude,
        InputScale::Display,
        InputScale::Dn,
    ];

    /// Whether values in this scale are sigma0 (calibrated), so that their level in dB means
    /// something: not a display stretch's grey levels nor uncalibrated digital numbers.
    pub fn calibrated(self) -> bool {
        !matches!(self, InputScale::Display | InputScale::Dn)
    }

    pub fn name(self) -> &'static str {
        match self {
            InputScale::Linear => "linear",
            InputScale::Db => "db",
            InputScale::Amplitude => "amplitude",
            InputScale::Display => "display",
            InputScale::Dn => "dn",
        }
    }
}

impl std::fmt::Display for InputScale {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for InputScale {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        wakelab_schema::recipe::parse_named(s, &Self::ALL, Self::name, "a scale")
    }
}

/// The scale a band's unit states ("dB", "decibel", "linear", "amplitude"), if any.
pub fn from_unit(unit: &str) -> Option<InputScale> {
    let u = unit.trim().to_ascii_lowercase();
    if u == "db" || u.starts_with("decibel") {
        Some(InputScale::Db)
    } else if u == "linear" || u == "1" || u == "m2/m2" || u == "m^2/m^2" {
        Some(InputScale::Linear)
    } else if u == "amplitude" {
        Some(InputScale::Amplitude)
    } else {
        None
    }
}

/// Statistics of the valid (non-NaN) values.
struct Summary {
    valid: usize,
    negative: usize,
    min: f64,
    max: f64,
    median: f64,
    integral: bool,
}

fn summary(image: &Array2<f32>) -> Summary {
    let values: Vec<f32> = image.iter().copied().filter(|v| v.is_finite()).collect();
    let negative = values.iter().filter(|&&v| v < 0.0).count();
    let (min, max) = values.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &v| {
        (lo.min(v as f64), hi.max(v as f64))
    });
    let integral = values.iter().all(|v| v.fract() == 0.0);
    Summary {
        valid: values.len(),
        negative,
        min,
        max,
        median: wakelab_core::io::geotiff::quantile(&values, 0.5),
        integral,
    }
}

fn scale_error(value: String, allowed: String) -> ConfigError {
    ConfigError::new("--scale", value, allowed)
}

/// Turn `image` (NaN where masked), stated to be in `scale`, into linear sigma0 in place.
/// Slightly negative linear values are raised to `floor` (the noise-equivalent sigma0 at the
/// pixel, or [`MIN_SIGMA0`]), and zero digital numbers to half a step; returns how many were.
/// Refused, naming the count and range: a linear, amplitude or dn image with more than half
/// its pixels negative (it is in dB), a linear or amplitude image whose median is above +10 dB
/// (dB of a bright scene, digital numbers or a display stretch), a dB image whose values are
/// all in [0, 1] (linear sigma0) or that holds 8-bit grey levels (a display stretch).
pub fn to_linear_sigma0(
    image: &mut Array2<f32>,
    scale: InputScale,
    floor: &(dyn Fn(usize, usize) -> f64 + Sync),
) -> Result<usize, ConfigError> {
    let s = summary(image);
    if s.valid == 0 {
        return Ok(0);
    }
    let share = s.negative as f64 / s.valid as f64;
    let range = format!("values {:.4} to {:.4}, median {:.4}", s.min, s.max, s.median);
    match scale {
        InputScale::Linear | InputScale::Amplitude => {
            if share > 0.5 {
                return Err(scale_error(
                    scale.name().into(),
                    format!(
                        "{} of {} valid pixels are negative ({range}): sigma0 in dB? pass --scale db",
                        s.negative, s.valid
                    ),
                ));
            }
            let median_power = if scale == InputScale::Amplitude {
                s.median * s.median
            } else {
                s.median
            };
            if median_power > MAX_SEA_MEDIAN {
                let hint = if s.integral && s.max <= 255.0 {
                    "an 8-bit display image? pass --scale display"
                } else if s.integral {
                    "digital numbers? calibrate the product first (wakelab calibrate reads Sentinel-1 SAFE products), or pass --scale dn to read them as amplitude up to an unknown gain"
                } else {
                    "not sigma0: calibrate it, or state its scale with --scale db|amplitude|dn|display"
                };
                return Err(scale_error(
                    scale.name().into(),
                    format!(
                        "its median is {:.1} dB as {scale} sigma0, brighter than any sea ({range}): {hint}",
                        10.0 * median_power.log10()
                    ),
                ));
            }
        }
        InputScale::Dn => {
            if share > 0.5 {
                return Err(scale_error(
                    "dn".into(),
                    format!(
                        "{} of {} valid pixels are negative ({range}): digital numbers of amplitude are not; sigma0 in dB? pass --scale db",
                        s.negative, s.valid
                    ),
                ));
            }
        }
        InputScale::Db => {
            if s.min >= 0.0 && s.max <= 1.0 {
                return Err(scale_error(
                    "db".into(),
                    format!("every value is in [0, 1] ({range}): linear sigma0, not dB? pass --scale linear"),
                ));
            }
            if s.min >= 0.0 && s.integral && s.max > 60.0 {
                return Err(scale_error(
                    "db".into(),
                    format!("the values are non-negative integers up to {} ({range}): an 8-bit display image? pass --scale display", s.max),
                ));
            }
        }
        InputScale::Display => {}
    }
    let floored = std::sync::atomic::AtomicUsize::new(0);
    image
        .axis_iter_mut(ndarray::Axis(0))
        .into_par_iter()
        .enumerate()
        .for_each(|(r, mut row)| {
            let mut count = 0;
            for (c, v) in row.iter_mut().enumerate() {
                if v.is_nan() {
                    continue;
                }
                *v = match scale {
                    InputScale::Linear => *v,
                    InputScale::Amplitude | InputScale::Dn => *v * *v,
                    InputScale::Db | InputScale::Display => 10f32.powf(*v / 10.0),
                };
                if *v <= 0.0 {
                    match scale {
                        InputScale::Linear | InputScale::Amplitude => *v = floor(r, c) as f32,
                        // a zero digital number lies under the quantisation step: half a step
                        // (the floor in sigma0 means nothing on an uncalibrated scale)
                        InputScale::Dn => *v = DN_FLOOR * DN_FLOOR,
                        InputScale::Db | InputScale::Display => continue,
                    }
                    count += 1;
                }
            }
            floored.fetch_add(count, std::sync::atomic::Ordering::Relaxed);
        });
    Ok(floored.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    fn min_floor(_: usize, _: usize) -> f64 {
        MIN_SIGMA0
    }

    #[test]
    fn db_read_as_linear_is_refused_with_the_count_and_range() {
        let mut db = array![[-20.0f32, -18.5], [-22.0, 1.0]];
        let e = to_linear_sigma0(&mut db, InputScale::Linear, &min_floor).unwrap_err();
        assert_eq!(e.field, "--scale");
        assert!(e.allowed.contains("3 of 4 valid pixels are negative"), "{}", e.allowed);
        assert!(e.allowed.contains("-22.0000 to 1.0000"), "{}", e.allowed);
        assert!(e.allowed.contains("--scale db"));
    }

    #[test]
    fn slight_negatives_are_floored_and_counted_never_zero() {
        let mut noisy = array![[0.01f32, -0.0001], [0.02, 0.0], [0.015, f32::NAN]];
        let floored = to_linear_sigma0(&mut noisy, InputScale::Linear, &min_floor).unwrap();
        assert_eq!(floored, 2);
        assert_eq!(noisy[[0, 1]], MIN_SIGMA0 as f32);
        assert_eq!(noisy[[1, 1]], MIN_SIGMA0 as f32);
        assert!(noisy[[2, 1]].is_nan());
        assert!(noisy.iter().all(|v| v.is_nan() || *v > 0.0));
    }

    #[test]
    fn linear_read_as_db_and_display_read_as_anything_else_are_refused() {
        let mut linear = array![[0.01f32, 0.02], [0.05, 0.03]];
        let e = to_linear_sigma0(&mut linear, InputScale::Db, &min_floor).unwrap_err();
        assert!(e.allowed.contains("--scale linear"), "{}", e.allowed);
        let grey = array![[12.0f32, 200.0], [130.0, 140.0]];
        let e = to_linear_sigma0(&mut grey.clone(), InputScale::Db, &min_floor).unwrap_err();
        assert!(e.allowed.contains("--scale display"), "{}", e.allowed);
        let e = to_linear_sigma0(&mut grey.clone(), InputScale::Linear, &min_floor).unwrap_err();
        assert!(e.allowed.contains("--scale display"), "{}", e.allowed);
        // as display: 10^(v/10), whose dB are the grey levels themselves
        let mut shown = grey.clone();
        to_linear_sigma0(&mut shown, InputScale::Display, &min_floor).unwrap();
        assert!((10.0 * (shown[[1, 0]] as f64).log10() - 130.0).abs() < 1e-3);
    }

    #[test]
    fn scales_convert_to_the_same_sigma0() {
        let sigma0 = 0.0316f32;
        let mut db = array![[10.0 * sigma0.log10(), -10.0]];
        let mut amplitude = array![[sigma0.sqrt(), 0.3]];
        to_linear_sigma0(&mut db, InputScale::Db, &min_floor).unwrap();
        to_linear_sigma0(&mut amplitude, InputScale::Amplitude, &min_floor).unwrap();
        assert!((db[[0, 0]] - sigma0).abs() < 1e-6 && (amplitude[[0, 0]] - sigma0).abs() < 1e-6);
        assert_eq!(from_unit("dB"), Some(InputScale::Db));
        assert_eq!(from_unit("K"), None);
        assert_eq!("DB".parse::<InputScale>(), Ok(InputScale::Db));
    }

    /// Digital numbers of amplitude, DN = A sqrt(sigma0) with a gain A the file does not give
    /// (Sentinel-1's sigma0 = DN^2 / A^2): refused as amplitude with the flag to pass, read as
    /// `dn` to A^2 sigma0, whose dB differ from sigma0's by one offset (20 log10 A), so every
    /// contrast in dB is sigma0's. A zero is half a step; mostly negative values are dB.
    #[test]
    fn digital_numbers_read_as_sigma0_up_to_one_gain() {
        let gain = 3000.0f32;
        let sigma0 = array![[0.01f32, 0.02], [0.005, 0.3]];
        let dn = sigma0.mapv(|s| (gain * s.sqrt()).round());
        let e = to_linear_sigma0(&mut dn.clone(), InputScale::Amplitude, &min_floor).unwrap_err();
        assert!(e.allowed.contains("pass --scale dn"), "{}", e.allowed);
        let mut read = dn.clone();
        assert_eq!(to_linear_sigma0(&mut read, InputScale::Dn, &min_floor).unwrap(), 0);
        let db = |v: f32| 10.0 * (v as f64).log10();
        let offset = 20.0 * (gain as f64).log10();
        for (r, s) in read.iter().zip(&sigma0) {
            // the rounding to whole numbers moves the dB by under 0.01 at these levels
            assert!((db(*r) - db(*s) - offset).abs() < 0.01, "{r} {s}");
        }
        assert!(((db(read[[1, 1]]) - db(read[[0, 0]])) - 10.0 * 30f64.log10()).abs() < 0.01);
        let mut zero = array![[0.0f32, 300.0], [f32::NAN, 250.0]];
        assert_eq!(to_linear_sigma0(&mut zero, InputScale::Dn, &min_floor).unwrap(), 1);
        assert_eq!(zero[[0, 0]], DN_FLOOR * DN_FLOOR);
        assert!(zero[[1, 0]].is_nan());
        let mut in_db = array![[-20.0f32, -18.0], [-25.0, 3.0]];
        let e = to_linear_sigma0(&mut in_db, InputScale::Dn, &min_floor).unwrap_err();
        assert!(e.allowed.contains("--scale db"), "{}", e.allowed);
        assert!(!InputScale::Dn.calibrated() && !InputScale::Display.calibrated());
        assert!(InputScale::Amplitude.calibrated());
        assert_eq!("dn".parse::<InputScale>(), Ok(InputScale::Dn));
    }
}
