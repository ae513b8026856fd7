//! TerraSAR-X, TanDEM-X and PAZ detected ground-range products (MGD): the product directory
//! (`TSX1_SAR__MGD_...`, `TDX1_SAR__...`, `PAZ1_SAR__...`) or its main XML. DLR's calibration
//! note (TSXX-ITD-TN-0049, "Radiometric Calibration of TerraSAR-X Data", Eqs. 1-3):
//!
//! beta0 = ks |DN|^2,  NEBN = ks sum_i c_i (tau - tau_ref)^i,  sigma0 = (ks |DN|^2 - NEBN) sin(theta),
//!
//! ks the layer's `calibration/calibrationConstant/calFactor`, c_i the `noise/imageNoise/
//! noiseEstimate` polynomial in slant-range time tau (records in azimuth time, interpolated
//! linearly between them), theta the incidence angle. Approximations, stated: tau and theta are
//! taken linear across the columns between the scene's first and last pixel (`sceneInfo/
//! rangeTime`, the corners' `incidenceAngle`), which a ground-range image follows to well under
//! a percent over a TerraSAR-X swath; the placement is the scene's centre and corners as GCPs
//! (GDAL's TSX driver reads a real product's GEOREF grid as no GCPs). Slant-range (SSC) and
//! geocoded (GEC, EEC) products are refused with what to do.

use crate::frame::{Gcp, Placement};
use crate::scale::floored_at_noise;
use crate::{Frame, Incidence, InputScale, PixelSpacing, Product, ProductMeta, ReadOptions, ReadReport};
use ndarray::Array2;
use roxmltree::{Document, Node};
use std::path::{Path, PathBuf};
use wakelab_core::WakelabError;

fn tsx_error(path: &Path, message: impl ToString) -> WakelabError {
    WakelabError::Image {
        path: path.display().to_string(),
        message: message.to_string(),
    }
}

/// The product's main XML when `path` is a TerraSAR-X, TanDEM-X or PAZ product directory or
/// that XML.
pub fn find(path: &Path) -> Option<PathBuf> {
    let is_product = |name: &str| {
        let upper = name.to_ascii_uppercase();
        ["TSX1_SAR", "TDX1_SAR", "PAZ1_SAR"]
            .iter()
            .any(|p| upper.starts_with(p))
    };
    let name = path.file_name()?.to_str()?;
    if path.is_dir() && is_product(name) {
        let xml = path.join(format!("{name}.xml"));
        return xml.is_file().then_some(xml);
    }
    (path.is_file() && is_product(name) && crate::extension(path) == "xml").then(|| path.to_path_buf())
}

fn child<'a, 'i>(node: Node<'a, 'i>, name: &str) -> Option<Node<'a, 'i>> {
    node.children().find(|n| n.has_tag_name(name))
}

/// The text at a path of child names below `node`.
fn text<'a>(node: Node<'a, '_>, path: &[&str]) -> Option<&'a str> {
    let mut n = node;
    for name in path {
        n = child(n, name)?;
    }
    n.text().map(str::trim)
}

fn number(node: Node, path: &[&str]) -> Option<f64> {
    text(node, path)?.parse().ok()
}

/// One noise record: its azimuth time (s from the scene start) and polynomial.
#[derive(Debug, Clone)]
struct NoiseRecord {
    time: f64,
    reference: f64,
    coefficients: Vec<f64>,
}

impl NoiseRecord {
    fn at(&self, tau: f64) -> f64 {
        let x = tau - self.reference;
        self.coefficients.iter().rev().fold(0.0, |acc, c| acc * x + c)
    }
}

/// Seconds of a UTC time `YYYY-MM-DDTHH:MM:SS.ffffffZ` from the start of its day.
fn seconds_of_day(t: &str) -> Option<f64> {
    let (_, time) = t.trim().trim_end_matches('Z').split_once('T')?;
    let mut parts = time.split(':');
    let h: f64 = parts.next()?.parse().ok()?;
    let m: f64 = parts.next()?.parse().ok()?;
    let s: f64 = parts.next()?.parse().ok()?;
    Some(h * 3600.0 + m * 60.0 + s)
}

/// Read a TerraSAR-X MGD product (module doc) as calibrated sigma0.
pub fn read(xml_path: &Path, options: &ReadOptions) -> Result<Product, WakelabError> {
    let err = |m: String| tsx_error(xml_path, m);
    let text_xml = std::fs::read_to_string(xml_path).map_err(|e| WakelabError::io(xml_path, e))?;
    let doc = Document::parse(&text_xml).map_err(|e| err(format!("not well-formed XML: {e}")))?;
    let root = doc.root_element();
    let info = child(root, "productInfo").ok_or_else(|| err("no <productInfo>".into()))?;
    let variant = text(info, &["productVariantInfo", "productVariant"]).unwrap_or("");
    if variant != "MGD" {
        return Err(err(format!(
            "a {variant} product; wakelab calibrates detected ground-range (MGD) TerraSAR-X products (SSC, GEC and EEC: calibrate in SNAP and pass the GeoTIFF)"
        )));
    }
    let raster = ["imageDataInfo", "imageRaster"];
    let need = |path: &[&str], what: &str| -> Result<f64, WakelabError> {
        number(info, path).ok_or_else(|| err(format!("no {what} (<{}>)", path.join("/"))))
    };
    let rows = need(&[raster[0], raster[1], "numberOfRows"], "row count")? as usize;
    let cols = need(&[raster[0], raster[1], "numberOfColumns"], "column count")? as usize;
    let layers: Vec<(String, PathBuf)> = child(root, "productComponents")
        .map(|c| {
            c.children()
                .filter(|n| n.has_tag_name("imageData"))
                .filter_map(|n| {
                    let pol = text(n, &["polLayer"])?.to_ascii_uppercase();
                    let dir = text(n, &["file", "location", "path"])?;
                    let name = text(n, &["file", "location", "filename"])?;
                    Some((pol, xml_path.parent()?.join(dir).join(name)))
                })
                .collect()
        })
        .unwrap_or_default();
    let available: Vec<String> = layers.iter().map(|l| l.0.clone()).collect();
    let wanted = match &options.polarisation {
        Some(p) => p.to_ascii_uppercase(),
        None => ["VV", "HH"]
            .into_iter()
            .find(|p| available.iter().any(|a| a == p))
            .unwrap_or_else(|| available.first().map_or("VV", String::as_str))
            .to_string(),
    };
    let Some((pol, image_path)) = layers.iter().find(|l| l.0 == wanted).cloned() else {
        return Err(wakelab_core::ConfigError::new(
            "--pol",
            wanted,
            format!("a polarisation the product holds: {}", available.join(", ")),
        )
        .into());
    };
    let layer = |section: &str, item: &str| {
        root.children()
            .filter(|n| n.has_tag_name(section))
            .flat_map(|n| {
                if section == "calibration" {
                    n.children().filter(|c| c.has_tag_name(item)).collect::<Vec<_>>()
                } else {
                    vec![n]
                }
            })
            .find(|n| text(*n, &["polLayer"]).is_some_and(|p| p.eq_ignore_ascii_case(&pol)))
    };
    let ks = layer("calibration", "calibrationConstant")
        .and_then(|n| number(n, &["calFactor"]))
        .ok_or_else(|| err(format!("no calFactor for {pol} (<calibration/calibrationConstant>)")))?;
    let start = text(info, &["sceneInfo", "start", "timeUTC"])
        .and_then(seconds_of_day)
        .ok_or_else(|| err("no scene start time (<sceneInfo/start/timeUTC>)".into()))?;
    // a scene over midnight: its stop on the next day
    let since_start = |t: f64| {
        if t < start - 43_200.0 {
            t + 86_400.0 - start
        } else {
            t - start
        }
    };
    let stop = text(info, &["sceneInfo", "stop", "timeUTC"])
        .and_then(seconds_of_day)
        .map_or(0.0, since_start);
    let mut records: Vec<NoiseRecord> = match layer("noise", "") {
        None => Vec::new(),
        Some(noise) => noise
            .children()
            .filter(|n| n.has_tag_name("imageNoise"))
            .filter_map(|n| {
                let estimate = child(n, "noiseEstimate")?;
                let degree = number(estimate, &["polynomialDegree"])? as usize;
                let mut coefficients = vec![0.0; degree + 1];
                for c in estimate.children().filter(|c| c.has_tag_name("coefficient")) {
                    let k: usize = c.attribute("exponent")?.parse().ok()?;
                    *coefficients.get_mut(k)? = c.text()?.trim().parse().ok()?;
                }
                Some(NoiseRecord {
                    time: since_start(text(n, &["timeUTC"]).and_then(seconds_of_day)?),
                    reference: number(estimate, &["referencePoint"])?,
                    coefficients,
                })
            })
            .collect(),
    };
    if records.is_empty() && !options.keep_noise {
        return Err(err(format!(
            "no noise estimate for {pol} (<noise/imageNoise/noiseEstimate>): pass --keep-noise to calibrate without removing it"
        )));
    }
    records.sort_by(|a, b| a.time.total_cmp(&b.time));
    let scene = child(info, "sceneInfo").ok_or_else(|| err("no <sceneInfo>".into()))?;
    let first_tau =
        number(scene, &["rangeTime", "firstPixel"]).ok_or_else(|| err("no <sceneInfo/rangeTime/firstPixel>".into()))?;
    let last_tau =
        number(scene, &["rangeTime", "lastPixel"]).ok_or_else(|| err("no <sceneInfo/rangeTime/lastPixel>".into()))?;
    // the scene's centre and corners: (1-based row, column, lat, lon, incidence)
    let points: Vec<(f64, f64, f64, f64, f64)> = scene
        .children()
        .filter(|n| n.has_tag_name("sceneCenterCoord") || n.has_tag_name("sceneCornerCoord"))
        .filter_map(|n| {
            Some((
                number(n, &["refRow"])?,
                number(n, &["refColumn"])?,
                number(n, &["lat"])?,
                number(n, &["lon"])?,
                number(n, &["incidenceAngle"])?,
            ))
        })
        .collect();
    if points.len() < 3 {
        return Err(err(
            "fewer than 3 scene corner coordinates (<sceneInfo/sceneCornerCoord>)".into(),
        ));
    }
    // incidence linear in column: a least-squares line through the corners and centre
    let n = points.len() as f64;
    let (mc, mi) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), p| (a + (p.1 - 1.0) / n, b + p.4 / n));
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(a, b), p| {
        let dx = p.1 - 1.0 - mc;
        (a + dx * (p.4 - mi), b + dx * dx)
    });
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    let theta = |col: f64| mi + slope * (col - mc);
    let tau = |col: f64| first_tau + (last_tau - first_tau) * col / (cols.max(2) - 1) as f64;
    // the image's digital numbers through GDAL
    let dataset = gdal::Dataset::open(&image_path).map_err(|e| {
        err(format!(
            "the product lacks its image {}{}",
            image_path.display(),
            crate::gdal_reason(&e)
        ))
    })?;
    let band = dataset
        .rasterband(1)
        .map_err(|e| crate::gdal_error(xml_path, "image band", e))?;
    if band.size() != (cols, rows) {
        return Err(err(format!(
            "its image is {} x {} pixels, its XML says {rows} x {cols}",
            band.size().1,
            band.size().0
        )));
    }
    let dn = band
        .read_as::<f32>((0, 0), (cols, rows), (cols, rows), None)
        .map_err(|e| crate::gdal_error(xml_path, "reading the image", e))?;
    let dn = Array2::from_shape_vec((rows, cols), dn.data().to_vec()).map_err(|e| err(e.to_string()))?;
    // per column: ks NEBN's polynomial per record, sin(theta)
    let sin: Vec<f64> = (0..cols).map(|c| theta(c as f64).to_radians().sin()).collect();
    let per_record: Vec<Vec<f64>> = records
        .iter()
        .map(|r| (0..cols).map(|c| ks * r.at(tau(c as f64))).collect())
        .collect();
    let row_time = |r: usize| stop * r as f64 / (rows.max(2) - 1) as f64;
    let mut image = Array2::<f32>::zeros((rows, cols));
    let mut masked = Array2::from_elem((rows, cols), false);
    crate::mask::border_zeros(&dn, &mut masked);
    let mut floored = 0;
    let mut nebn = vec![0.0; cols];
    for (r, mut out) in image.rows_mut().into_iter().enumerate() {
        if !options.keep_noise {
            let times: Vec<f64> = records.iter().map(|x| x.time).collect();
            let (i, t) = crate::sentinel1::lut::bracket(&times, row_time(r));
            for (c, v) in nebn.iter_mut().enumerate() {
                let a = per_record[i][c];
                *v = if t == 0.0 {
                    a
                } else {
                    a * (1.0 - t) + per_record[i + 1][c] * t
                };
            }
        }
        for (c, o) in out.iter_mut().enumerate() {
            if masked[[r, c]] {
                *o = f32::NAN;
                continue;
            }
            let d = dn[[r, c]] as f64;
            let (value, raised) = floored_at_noise((ks * d * d - nebn[c]) * sin[c], nebn[c] * sin[c]);
            *o = value;
            floored += raised as usize;
        }
    }
    let report = ReadReport::floored_after_noise_removal(floored);
    let wkt = gdal::spatial_ref::SpatialRef::from_epsg(4326)
        .and_then(|s| s.to_wkt())
        .unwrap_or_default();
    let frame = Frame {
        rows,
        cols,
        placement: Placement::Gcps {
            // refRow and refColumn count pixels from 1; a pixel's centre is at its index + 0.5
            gcps: points
                .iter()
                .map(|p| Gcp {
                    pixel: p.1 - 0.5,
                    line: p.0 - 0.5,
                    x: p.3,
                    y: p.2,
                    z: 0.0,
                })
                .collect(),
            wkt,
        },
    };
    let spacing = |what: &str| number(info, &[raster[0], raster[1], what]);
    let looks = |what: &str| number(info, &[raster[0], raster[1], what]);
    Ok(Product {
        path: xml_path.to_path_buf(),
        image,
        frame,
        meta: ProductMeta {
            format: "TerraSAR-X MGD".into(),
            product_id: crate::stem_of(xml_path),
            mission: text(info, &["missionInfo", "mission"]).map(str::to_string),
            band: Some(wakelab_schema::band::Band::X),
            acquisition_time: text(info, &["sceneInfo", "start", "timeUTC"]).map(str::to_string),
            polarisation: Some(pol),
            polarisations: available,
            pixel_spacing: spacing("rowSpacing")
                .zip(spacing("columnSpacing"))
                .map(|(r, c)| PixelSpacing::annotated(r, c)),
            looks: looks("azimuthLooks").zip(looks("rangeLooks")).map(|(a, r)| a * r),
            scale: Some(InputScale::Linear),
            calibrated: true,
            incidence: Some(Incidence {
                near_deg: theta(0.0),
                mid_deg: theta((cols - 1) as f64 / 2.0),
                far_deg: theta((cols - 1) as f64),
                grid: (0..3)
                    .flat_map(|k| {
                        let c = k as f64 * (cols - 1) as f64 / 2.0;
                        [(0.0, c, theta(c)), ((rows - 1) as f64, c, theta(c))]
                    })
                    .collect(),
            }),
            orbit_direction: text(info, &["missionInfo", "orbitDirection"]).map(str::to_ascii_uppercase),
            look_side: text(info, &["acquisitionInfo", "lookDirection"]).map(str::to_ascii_uppercase),
            slant_range_mid: Some(tau((cols - 1) as f64 / 2.0) * 299_792_458.0 / 2.0),
            platform_velocity: None,
            noise_removed: (!options.keep_noise).then(|| "NEBN polynomial (TSXX-ITD-TN-0049)".to_string()),
        },
        report,
    })
}
