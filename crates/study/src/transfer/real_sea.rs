//! Simulated wakes drawn onto real sea (issue 38, item 1: training that spans real
//! acquisitions). The detectors trained on simulated scenes alone learn the simulator's clutter
//! as well as the wake: on real images they rank ships with a wake and without at chance
//! (docs/results.md). Wake2Wake (IEEE TGRS 2024) trained on simulated wakes mixed into real SAR
//! data for the same reason. Here each simulated wake that shows in a training window is also
//! drawn onto a window of a real image without a wake, beside the same real window without it,
//! so that the two differ by the wake alone and the clutter around it is a real sensor's.
//!
//! The wake is carried as its change in dB (the calibrated scene with the wake over its twin
//! without it: both speckled alike, so the ratio is the wake's own change, its ship's return
//! included), scaled by the real window's robust spread over the simulated sea's. The detector
//! reads a window in units of its robust spread ([`wakelab_learn::data::detector_input`]), so
//! the wake then stands as many spreads out of the real sea as it stood out of the simulated
//! one, whatever the real image's scale: sigma0, dB, or a display stretch of unknown gain.

use super::real::{annotations, Annotation};
use super::results::{RealSeaThreshold, SeaAlarm};
use crate::product_scan::open_product;
use crate::steps::open_sea::Scanner;
use crate::Result;
use anyhow::{anyhow, Context};
use ndarray::{s, Array2, ArrayView2, Axis};
use rand::RngExt;
use std::path::Path;
use wakelab_learn::calibration::threshold_for_alarm_rate;
use wakelab_learn::data::{robust_centre_and_spread, robust_normalise, RadarScale};
use wakelab_learn::detect::{detect_image, fills_half_a_window, ScanOptions};
use wakelab_learn::device::Device;
use wakelab_learn::train::Example;
use wakelab_products::Source;
use wakelab_schema::band::Band;

/// Real windows each simulated wake window is drawn onto.
pub const PER_WAKE: usize = 2;

/// The real sea's alarms reported with their images, strongest first.
pub const STRONGEST: usize = 10;

/// One real image in dB, averaged to a detector's spacing, and its brightest value (a
/// display's ceiling, or its brightest target): no drawn wake is brighter. `name` and
/// `pixels_per_cell` (the image's own pixels per averaged pixel: rows, columns) place an alarm
/// back on the image as its user sees it.
#[derive(Debug)]
pub struct SeaImage {
    pub db: Array2<f32>,
    pub ceiling: f32,
    pub name: String,
    pub pixels_per_cell: (f64, f64),
}

/// The images of `dir`, each with its `NAME.geojson` as `--real` reads them, refused by name
/// where one draws a wake. Reads no pixels: a run checks its folder before it writes anything.
pub fn listed(dir: &Path) -> Result<Vec<Annotation>> {
    let geojson = |e: &std::fs::DirEntry| e.path().extension().is_some_and(|x| x == "geojson");
    let entries = std::fs::read_dir(dir)
        .with_context(|| format!("transfer.sea_images {}: not a readable folder", dir.display()))?;
    if !entries.flatten().any(|e| geojson(&e)) {
        return Err(anyhow!(
            "transfer.sea_images {}: no image with its NAME.geojson in it (an empty FeatureCollection for an image without a wake)",
            dir.display()
        ));
    }
    let listed = annotations(dir).with_context(|| format!("transfer.sea_images {}", dir.display()))?;
    if let Some(a) = listed.iter().find(|a| !a.wakes.is_empty()) {
        return Err(anyhow!(
            "transfer.sea_images: {} has {} wake(s) drawn; training draws wakes onto images without one \
             (score images with wakes with --real instead)",
            a.image.display(),
            a.wakes.len()
        ));
    }
    Ok(listed)
}

/// Every image of `dir` ([`listed`]), read as `detect` reads it, in dB, area-averaged to each
/// of `spacings` (m). An image coarser than a spacing is left out of that spacing's list; a
/// spacing left without any image is refused, naming it.
pub fn load(dir: &Path, spacings: &[f64]) -> Result<Vec<Vec<SeaImage>>> {
    averaged_images(
        listed(dir)?,
        dir,
        spacings,
        "sea_images",
        |annotation, (db, pixels_per_cell)| {
            let ceiling = db
                .iter()
                .copied()
                .filter(|v| v.is_finite())
                .fold(f32::NEG_INFINITY, f32::max);
            let name = annotation
                .image
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned();
            SeaImage {
                db,
                ceiling,
                name,
                pixels_per_cell,
            }
        },
    )
}

/// Each image of `listed` (of the folder `dir`, the plan's `field`) averaged to each of
/// `spacings` ([`averaged_db`]) and made a `T` by `make`, per spacing. An image coarser than a
/// spacing is left out of that spacing's list; a spacing left without any image is refused,
/// naming it: its detector would train on simulated windows alone.
pub(crate) fn averaged_images<T>(
    listed: Vec<Annotation>,
    dir: &Path,
    spacings: &[f64],
    field: &str,
    make: impl Fn(&Annotation, Averaged) -> T,
) -> Result<Vec<Vec<T>>> {
    let mut out: Vec<Vec<T>> = spacings.iter().map(|_| Vec::new()).collect();
    for annotation in listed {
        for (images, averaged) in out.iter_mut().zip(averaged_db(&annotation, spacings, field)?) {
            images.extend(averaged.map(|a| make(&annotation, a)));
        }
    }
    match out.iter().zip(spacings).find(|(images, _)| images.is_empty()) {
        Some((_, &spacing)) => Err(anyhow!(
            "transfer.{field} {}: no image is as fine as a detector's {spacing} m pixels; give images of {spacing} m or finer",
            dir.display()
        )),
        None => Ok(out),
    }
}

/// An image in dB averaged to a detector's spacing, and its pixels per averaged pixel (rows,
/// columns).
pub(crate) type Averaged = (Array2<f32>, (f64, f64));

/// The image of `annotation`, read as `detect` reads it, in dB (NaN for no data), area-averaged
/// to each of `spacings` (m), with the image's pixels per averaged pixel (rows, columns); None
/// for a spacing finer than the image's. An image without a stated spacing is refused, naming
/// the plan's `field`.
fn averaged_db(annotation: &Annotation, spacings: &[f64], field: &str) -> Result<Vec<Option<Averaged>>> {
    let path = &annotation.image;
    let opened = open_product(path, &annotation.read_options(), Band::C, true, &mut |_, _| {})?;
    let product = match opened.source {
        Source::Whole(product) => *product,
        Source::Rows(rows) => rows.read_all(&mut |_, _| {})?,
    };
    let spacing = product.meta.pixel_spacing.as_ref().ok_or_else(|| {
        anyhow!(
            "transfer.{field}: {} states no pixel spacing: give it as \"wakelab\": {{\"pixel_spacing_m\": M}} in its GeoJSON",
            path.display()
        )
    })?;
    Ok(spacings
        .iter()
        .map(|&target| {
            let factor = (target / spacing.rows, target / spacing.columns);
            if factor.0 < 1.0 || factor.1 < 1.0 {
                return None;
            }
            let averaged = wakelab_products::resample::area_average(&product.image, factor.0, factor.1);
            let db = averaged.mapv(|v| {
                if v.is_finite() {
                    RadarScale::Linear.decibels(v)
                } else {
                    f32::NAN
                }
            });
            Some((db, factor))
        })
        .collect())
}

/// The threshold at which `scanner` raises at most `per_1000_km2` alarms per 1,000 km^2 on the
/// real sea `images` (dB at its spacing), scanned as the simulated open sea is (half-window
/// stride, its separate alarms: [`threshold_for_alarm_rate`]); None without images. Images too
/// small for a scan (under half a window) are left out. Item 5 of issue 38 sets the threshold
/// for a stated rate on simulated open sea; where the user gives real sea, the detector's
/// threshold holds the rate on both. The [`STRONGEST`] alarms are kept with their images: a
/// wake in the "wake-free" sea raises the threshold, and they are where a user looks for one.
pub(crate) fn threshold(
    scanner: &Scanner,
    images: &[SeaImage],
    per_1000_km2: f64,
    device: &Device,
) -> Result<Option<RealSeaThreshold>> {
    if images.is_empty() {
        return Ok(None);
    }
    let n = scanner.info.input_size;
    let spacing = scanner.info.pixel_spacing.unwrap_or(f64::NAN);
    let options = ScanOptions {
        stride: Some((n / 2).max(1)),
        scale: RadarScale::Db,
        threshold: Some(0.0),
        ..ScanOptions::default()
    };
    let (mut alarms, mut strongest, mut km2, mut scanned) = (Vec::new(), Vec::new(), 0.0, 0);
    for image in images.iter().filter(|i| fills_half_a_window(i.db.dim(), n)) {
        let found = detect_image(
            &scanner.detector,
            &scanner.info,
            &image.db,
            options,
            device,
            &mut |_, _| {},
        )?;
        alarms.extend(found.detections.iter().map(|d| d.score));
        let (rows, columns) = image.pixels_per_cell;
        strongest.extend(found.detections.iter().map(|d| SeaAlarm {
            image: image.name.clone(),
            // in the image's own pixels, as `detect` places a detection on its product
            row: d.row * rows,
            col: d.col * columns,
            probability: d.score,
        }));
        strongest.sort_by(|a, b| b.probability.total_cmp(&a.probability));
        strongest.truncate(STRONGEST);
        km2 += image.db.iter().filter(|v| v.is_finite()).count() as f64 * spacing * spacing / 1e6;
        scanned += 1;
    }
    Ok(Some(RealSeaThreshold {
        images: scanned,
        km2,
        threshold: threshold_for_alarm_rate(&alarms, km2, per_1000_km2),
        alarms_at_threshold: f64::NAN,
        alarms,
        strongest,
    }))
}

/// The files of `dir` (a link read as its target; folders left out), each name with its size
/// in bytes, in name order; none where `dir` cannot be read (loading it then says why).
pub(crate) fn files(dir: &Path) -> Vec<(std::ffi::OsString, u64)> {
    let mut files: Vec<_> = (std::fs::read_dir(dir).into_iter().flatten().flatten())
        .filter_map(|e| {
            let metadata = std::fs::metadata(e.path()).ok().filter(|m| m.is_file())?;
            Some((e.file_name(), metadata.len()))
        })
        .collect();
    files.sort();
    files
}

/// [`files`] as `NAME:SIZE` words: what a run's reuse key holds of a folder.
pub fn listing(dir: &Path) -> String {
    let words: Vec<String> = (files(dir).iter())
        .map(|(name, size)| format!("{}:{size}", name.to_string_lossy()))
        .collect();
    words.join(" ")
}

/// A window of side `n` of one of `images` drawn at random, every pixel of it valid and not all
/// alike, and that image's ceiling; none after 20 draws.
pub(crate) fn sea_window(images: &[SeaImage], n: usize, rng: &mut impl rand::Rng) -> Option<(Array2<f32>, f32)> {
    let fits: Vec<&SeaImage> = images
        .iter()
        .filter(|i| i.db.nrows() >= n && i.db.ncols() >= n)
        .collect();
    if fits.is_empty() {
        return None;
    }
    for _ in 0..20 {
        let image = fits[rng.random_range(0..fits.len())];
        let r = rng.random_range(0..=image.db.nrows() - n);
        let c = rng.random_range(0..=image.db.ncols() - n);
        let window = image.db.slice(s![r..r + n, c..c + n]);
        if window.iter().all(|v| v.is_finite()) && spread(&window) > 0.0 {
            return Some((window.to_owned(), image.ceiling));
        }
    }
    None
}

/// The robust spread the detector's input divides by ([`robust_centre_and_spread`]).
fn spread(window: &ArrayView2<f32>) -> f32 {
    robust_centre_and_spread(&window.to_owned()).1 as f32
}

/// The simulated wake of the window pair `with` / `without` (calibrated sigma0, the same
/// window of a scene with its wake and of its twin) drawn onto the real window `sea` (dB,
/// its image's `ceiling`), and `sea` as it is: a wake (label 1) and its real twin (label 0),
/// as detector inputs.
pub(crate) fn wake_on_real_sea(
    with: ArrayView2<f32>,
    without: ArrayView2<f32>,
    sea: Array2<f32>,
    ceiling: f32,
) -> [Example; 2] {
    let db = |v: &f32| RadarScale::Linear.decibels(*v);
    let (with, without) = (with.map(db), without.map(db));
    let simulated = spread(&without.view());
    let gain = if simulated > 0.0 {
        spread(&sea.view()) / simulated
    } else {
        0.0
    };
    let mut drawn = sea.clone();
    ndarray::Zip::from(&mut drawn)
        .and(&with)
        .and(&without)
        .for_each(|d, &w, &o| *d = (*d + gain * (w - o)).min(ceiling));
    let example = |image: Array2<f32>, label| Example {
        image: robust_normalise(image).insert_axis(Axis(0)),
        label,
        mask: None,
    };
    [example(drawn, 1), example(sea, 0)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use wakelab_learn::data::median;

    fn speckle(n: usize, looks: usize, rng: &mut impl rand::Rng) -> Array2<f32> {
        Array2::from_shape_fn((n, n), |_| {
            (0..looks).map(|_| -rng.random_range(1e-9f32..1.0).ln()).sum::<f32>() / looks as f32
        })
    }

    /// A simulated wake (a band 3 dB dark in 4-look speckle) drawn onto a "real" sea of other
    /// speckle shown as a display image of 6 grey levels per dB: the band stands as many robust
    /// spreads under the real sea as it stood under the simulated one (the detector's input is
    /// the same wake), and the twin is the real window itself, normalised.
    #[test]
    fn a_drawn_wake_stands_out_of_real_sea_as_far_as_out_of_the_simulated() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let n = 64;
        let without = speckle(n, 4, &mut rng);
        let mut with = without.clone();
        with.slice_mut(s![30..34, ..]).mapv_inplace(|v| v * 10f32.powf(-0.3));
        // a display image: grey = 120 + 6 x dB of 16-look speckle, read as dB (`--scale display`)
        let real = speckle(n, 16, &mut rng).mapv(|v| 120.0 + 6.0 * 10.0 * v.log10());
        let [wake, twin] = wake_on_real_sea(with.view(), without.view(), real.clone(), 255.0);
        assert_eq!((wake.label, twin.label), (1, 0));
        assert_eq!(twin.image.index_axis(Axis(0), 0), robust_normalise(real));
        let band = |image: &Array2<f32>| image.slice(s![30..34, ..]).mean().unwrap();
        let simulated = robust_normalise(without.mapv(|v| RadarScale::Linear.decibels(v)));
        let shift_sim = band(&robust_normalise(with.mapv(|v| RadarScale::Linear.decibels(v)))) - band(&simulated);
        let shift_real =
            band(&wake.image.index_axis(Axis(0), 0).to_owned()) - band(&twin.image.index_axis(Axis(0), 0).to_owned());
        assert!(shift_sim < -1.0, "{shift_sim}");
        assert!(
            (shift_real / shift_sim - 1.0).abs() < 0.1,
            "real {shift_real}, simulated {shift_sim}"
        );
    }

    /// A folder of two display images at 10 m: each averaged 2 x 2 to 20 m and 4 x 4 to 40 m,
    /// in dB (a display's grey level read as dB is itself); one at 30 m is left out of the 20 m
    /// list; an image with a wake drawn, or none with its GeoJSON, is refused by name.
    #[test]
    fn sea_images_load_averaged_to_each_spacing_and_refuse_a_wake() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let sea = |name: &str, spacing: f64, features: &str| {
            let grey = image::GrayImage::from_fn(64, 48, |x, y| image::Luma([(100 + (x + y) % 7) as u8]));
            grey.save(d.join(format!("{name}.png"))).unwrap();
            let json = format!(
                r#"{{"type": "FeatureCollection", "wakelab": {{"coordinates": "pixel", "pixel_spacing_m": {spacing}, "scale": "display"}}, "features": [{features}]}}"#
            );
            std::fs::write(d.join(format!("{name}.geojson")), json).unwrap();
        };
        let e = format!("{:#}", load(d, &[20.0]).unwrap_err());
        assert!(e.contains("no image with its NAME.geojson"), "{e}");
        sea("a", 10.0, "");
        sea("b", 10.0, "");
        sea("c", 30.0, "");
        let loaded = load(d, &[20.0, 40.0]).unwrap();
        let dims = |l: &Vec<SeaImage>| l.iter().map(|i| i.db.dim()).collect::<Vec<_>>();
        assert_eq!(dims(&loaded[0]), vec![(24, 32), (24, 32)]);
        assert_eq!(dims(&loaded[1]), vec![(12, 16), (12, 16), (36, 48)]);
        let mean: f32 = loaded[0][0].db.mean().unwrap();
        assert!((mean - 103.0).abs() < 0.5, "{mean}");
        assert!(loaded[0][0].ceiling <= 106.0 && loaded[0][0].ceiling > 100.0);
        let e = format!("{:#}", load(d, &[5.0, 20.0]).unwrap_err());
        assert!(e.contains("no image is as fine as a detector's 5 m pixels"), "{e}");
        sea(
            "b",
            10.0,
            r#"{"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": [[1, 2], [30, 40]]}}"#,
        );
        let e = format!("{:#}", load(d, &[20.0]).unwrap_err());
        assert!(e.contains("b.png has 1 wake(s) drawn"), "{e}");
    }

    /// A ship's return drawn onto a display image is no brighter than that image's ceiling.
    #[test]
    fn a_drawn_return_stops_at_the_images_ceiling() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let without = speckle(32, 4, &mut rng);
        let mut with = without.clone();
        with[[16, 16]] *= 1e4;
        let real = speckle(32, 16, &mut rng).mapv(|v| 120.0 + 6.0 * 10.0 * v.log10());
        let ceiling = 200.0;
        let [wake, _] = wake_on_real_sea(with.view(), without.view(), real.clone(), ceiling);
        let drawn = wake.image.index_axis(Axis(0), 0);
        let top = drawn.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        assert_eq!(drawn[[16, 16]], top);
        let twin = robust_normalise(real.clone());
        let centre = median(&real);
        let mad = 1.4826 * median(&real.mapv(|v| (v - centre).abs()));
        assert!(
            (drawn[[16, 16]] - (ceiling - centre) / mad).abs() < 0.05 * drawn[[16, 16]].abs(),
            "{}",
            drawn[[16, 16]]
        );
        assert!(twin.iter().all(|&v| v < drawn[[16, 16]]));
    }
}
