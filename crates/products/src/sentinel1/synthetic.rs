//! A Sentinel-1 GRD product in ESA's SAFE layout (S1-RS-MDA-52-7441: manifest.safe, product,
//! calibration and noise annotation, measurement TIFF in one-row strips), of any size and with
//! any digital numbers, for tests, benchmarks and examples: GDAL's SAFE driver opens it. Its
//! look-up tables sample functions that bilinear interpolation reproduces exactly
//! (a + b l + c p + d l p), so the sigma0 of every pixel is known in closed form
//! ([`expected_sigma0`]), independently of the reader's interpolation. Writing panics on an
//! I/O error (it serves tests and benchmarks).

use gdal::raster::Buffer;
use gdal::DriverManager;
use rayon::prelude::*;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// The size of the small product of the tests.
pub const LINES: usize = 48;
pub const SAMPLES: usize = 64;
pub const STEM: &str = "s1a-iw-grd-vv-20200101t000000-20200101t000001-000001-000001-001";
pub const SAFE: &str = "S1A_IW_GRDH_1SDV_20200101T000000_20200101T000001_000001_000001_0001.SAFE";

impl Synthetic<'_> {
    /// (line, pixel) as fractions of the image, u and v in [0, 1].
    fn uv(&self, l: f64, p: f64) -> (f64, f64) {
        (l / (self.lines - 1) as f64, p / (self.samples - 1) as f64)
    }

    /// The calibration's sigmaNought A(line, pixel): 400 to 700, bilinear.
    pub fn gain(&self, l: f64, p: f64) -> f64 {
        let (u, v) = self.uv(l, p);
        400.0 + 100.0 * u + 150.0 * v + 50.0 * u * v
    }

    /// The noise range LUT (DN^2): with the gain, a noise-equivalent sigma0 near -22 dB.
    pub fn noise_range(&self, l: f64, p: f64) -> f64 {
        let (u, v) = self.uv(l, p);
        1000.0 + 300.0 * u + 600.0 * v + 100.0 * u * v
    }

    /// The first sample of the second azimuth noise block (the blocks split the swath in two).
    fn split(&self) -> usize {
        self.samples / 2
    }

    /// The azimuth noise factor: linear in line, rising in the first block, falling in the
    /// second.
    pub fn noise_azimuth(&self, l: f64, p: f64) -> f64 {
        let (u, _) = self.uv(l, p);
        if (p as usize) < self.split() {
            1.0 + 0.5 * u
        } else {
            1.5 - 0.5 * u
        }
    }
}

/// The small product's digital number at (line, pixel): zero left of pixel 4 (no data), and right of pixel 61
/// on the last 8 lines; 10 at (20, 30), below the noise there; else a scrambled level.
pub fn dn(l: usize, p: usize) -> u16 {
    if p < 4 || (l >= LINES - 8 && p > 61) {
        return 0;
    }
    if (l, p) == (20, 30) {
        return 10;
    }
    let h = (l * 7919 + p * 104_729) as u64;
    (200 + (h.wrapping_mul(2_654_435_761) >> 7) % 2800) as u16
}

/// A product to write: its size and its digital numbers.
pub struct Synthetic<'a> {
    pub lines: usize,
    pub samples: usize,
    /// IPF >= 2.9's noise annotation (range and azimuth), else the older range LUT.
    pub since_2_9: bool,
    pub dn: &'a (dyn Fn(usize, usize) -> u16 + Sync),
}

impl Synthetic<'static> {
    /// The tests' small product ([`LINES`] x [`SAMPLES`], [`dn`]).
    pub fn small(since_2_9: bool) -> Self {
        Self {
            lines: LINES,
            samples: SAMPLES,
            since_2_9,
            dn: &dn,
        }
    }
}

/// Knots (four, at the first and last line or pixel and between) of the LUT vectors.
fn knots(n: usize) -> [usize; 4] {
    [0, (n - 1) / 3, 2 * (n - 1) / 3, n - 1]
}

/// The geolocation grid: latitude and longitude affine in line and pixel.
/// (10 m of latitude per line: 1 / 11,113.2 degrees at 45 N on WGS 84; 10 m of longitude per
/// pixel: 1 / 7,884.7 degrees there, NGA's lengths of a degree.)
pub fn latitude(l: f64) -> f64 {
    45.0 + l / 11_113.209
}
pub fn longitude(p: f64) -> f64 {
    7.0 + p / 7_884.681
}
pub fn incidence(p: f64) -> f64 {
    30.0 + 0.2 * p
}

fn list(values: impl Iterator<Item = f64>) -> String {
    values.map(|v| format!("{v:e}")).collect::<Vec<_>>().join(" ")
}

fn header(root: &str) -> String {
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<{root}>\n  <adsHeader>\n    <missionId>S1A</missionId>\n    <productType>GRD</productType>\n    <polarisation>VV</polarisation>\n    <mode>IW</mode>\n    <swath>IW</swath>\n    <startTime>2020-01-01T00:00:00.000000</startTime>\n    <stopTime>2020-01-01T00:00:01.175000</stopTime>\n    <absoluteOrbitNumber>1</absoluteOrbitNumber>\n    <missionDataTakeId>1</missionDataTakeId>\n    <imageNumber>001</imageNumber>\n  </adsHeader>\n"
    )
}

fn vectors(s: &Synthetic, list_name: &str, vector: &str, values: &str, f: &dyn Fn(f64, f64) -> f64) -> String {
    let mut x = format!("  <{list_name} count=\"4\">\n");
    for l in knots(s.lines) {
        let pixels = list(knots(s.samples).iter().map(|&p| p as f64));
        let v = list(knots(s.samples).iter().map(|&p| f(l as f64, p as f64)));
        writeln!(
            x,
            "    <{vector}>\n      <azimuthTime>2020-01-01T00:00:00.000000</azimuthTime>\n      <line>{l}</line>\n      <pixel count=\"4\">{pixels}</pixel>\n      <{values} count=\"4\">{v}</{values}>\n    </{vector}>"
        )
        .unwrap();
    }
    x + &format!("  </{list_name}>\n")
}

pub fn calibration_xml(s: &Synthetic) -> String {
    header("calibration")
        + &vectors(
            s,
            "calibrationVectorList",
            "calibrationVector",
            "sigmaNought",
            &|l, p| s.gain(l, p),
        )
        + "</calibration>\n"
}

/// The noise annotation, in IPF >= 2.9's form (range and azimuth) or the older one.
pub fn noise_xml(s: &Synthetic) -> String {
    if !s.since_2_9 {
        return header("noise")
            + &vectors(s, "noiseVectorList", "noiseVector", "noiseLut", &|l, p| {
                s.noise_range(l, p)
            })
            + "</noise>\n";
    }
    let mut x = header("noise")
        + &vectors(
            s,
            "noiseRangeVectorList",
            "noiseRangeVector",
            "noiseRangeLut",
            &|l, p| s.noise_range(l, p),
        );
    x += "  <noiseAzimuthVectorList count=\"2\">\n";
    for (first, last) in [(0, s.split() - 1), (s.split(), s.samples - 1)] {
        let lines = [0.0, (s.lines - 1) as f64];
        write!(
            x,
            "    <noiseAzimuthVector>\n      <swath>IW1</swath>\n      <firstAzimuthLine>0</firstAzimuthLine>\n      <firstRangeSample>{first}</firstRangeSample>\n      <lastAzimuthLine>{}</lastAzimuthLine>\n      <lastRangeSample>{last}</lastRangeSample>\n      <line count=\"2\">{}</line>\n      <noiseAzimuthLut count=\"2\">{}</noiseAzimuthLut>\n    </noiseAzimuthVector>\n",
            s.lines - 1,
            list(lines.iter().copied()),
            list(lines.iter().map(|&l| s.noise_azimuth(l, first as f64)))
        )
        .unwrap();
    }
    x + "  </noiseAzimuthVectorList>\n</noise>\n"
}

pub fn product_xml(s: &Synthetic) -> String {
    let mut grid = String::new();
    let grid_lines = [0, (s.lines - 1) / 2, s.lines - 1];
    for &l in &grid_lines {
        for p in knots(s.samples) {
            write!(
                grid,
                "      <geolocationGridPoint>\n        <azimuthTime>2020-01-01T00:00:00.000000</azimuthTime>\n        <slantRangeTime>{:e}</slantRangeTime>\n        <line>{l}</line>\n        <pixel>{p}</pixel>\n        <latitude>{}</latitude>\n        <longitude>{}</longitude>\n        <height>0</height>\n        <incidenceAngle>{}</incidenceAngle>\n        <elevationAngle>30.0</elevationAngle>\n      </geolocationGridPoint>\n",
                5.3e-3 + 1e-7 * p as f64,
                latitude(l as f64),
                longitude(p as f64),
                incidence(p as f64)
            )
            .unwrap();
        }
    }
    header("product")
        + "  <generalAnnotation>\n    <productInformation>\n      <pass>Ascending</pass>\n    </productInformation>\n"
        + "    <orbitList count=\"1\">\n      <orbit>\n        <time>2020-01-01T00:00:00.000000</time>\n        <frame>Earth Fixed</frame>\n        <position><x>1</x><y>2</y><z>3</z></position>\n        <velocity><x>7000</x><y>2000</y><z>1000</z></velocity>\n      </orbit>\n    </orbitList>\n  </generalAnnotation>\n"
        + &format!("  <imageAnnotation>\n    <imageInformation>\n      <rangePixelSpacing>1.0e+01</rangePixelSpacing>\n      <azimuthPixelSpacing>1.0e+01</azimuthPixelSpacing>\n      <outputPixels>16 bit Unsigned Integer</outputPixels>\n      <numberOfSamples>{}</numberOfSamples>\n      <numberOfLines>{}</numberOfLines>\n    </imageInformation>\n", s.samples, s.lines)
        + "    <processingInformation>\n      <ellipsoidName>WGS84</ellipsoidName>\n      <ellipsoidSemiMajorAxis>6.378137e+06</ellipsoidSemiMajorAxis>\n      <ellipsoidSemiMinorAxis>6.356752314245179e+06</ellipsoidSemiMinorAxis>\n      <swathProcParamsList count=\"1\"><swathProcParams><rangeProcessing><numberOfLooks>5</numberOfLooks></rangeProcessing><azimuthProcessing><numberOfLooks>1</numberOfLooks></azimuthProcessing></swathProcParams></swathProcParamsList>\n    </processingInformation>\n  </imageAnnotation>\n"
        + &format!("  <geolocationGrid>\n    <geolocationGridPointList count=\"{}\">\n{grid}    </geolocationGridPointList>\n  </geolocationGrid>\n</product>\n", grid_lines.len() * 4)
}

/// The manifest: the XFDU structure GDAL's SAFE driver walks (a measurement data unit whose
/// dmdID names the annotation, calibration and noise metadata objects).
pub fn manifest_xml() -> String {
    let object = |id: &str, rep: &str, href: &str, mime: &str| {
        format!("    <dataObject ID=\"{id}\" repID=\"{rep}\"><byteStream mimeType=\"{mime}\"><fileLocation locatorType=\"URL\" href=\"./{href}\"/></byteStream></dataObject>\n")
    };
    let meta = |id: &str, data: &str| {
        format!("    <metadataObject ID=\"{id}\" classification=\"DESCRIPTION\" category=\"DMD\"><dataObjectPointer dataObjectID=\"{data}\"/></metadataObject>\n")
    };
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<xfdu:XFDU xmlns:xfdu=\"urn:ccsds:schema:xfdu:1\" xmlns:safe=\"http://www.esa.int/safe/sentinel-1.0\" version=\"esa/safe/sentinel-1.0/sentinel-1/sar/level-1/grd/standard/iwdp\">\n  <informationPackageMap>\n    <xfdu:contentUnit unitType=\"SAFE Archive Information Package\">\n      <xfdu:contentUnit unitType=\"Measurement Data Unit\" repID=\"s1Level1MeasurementSchema\" dmdID=\"productAnnotationVV calibrationAnnotationVV noiseAnnotationVV\">\n        <dataObjectPointer dataObjectID=\"measurementVV\"/>\n      </xfdu:contentUnit>\n    </xfdu:contentUnit>\n  </informationPackageMap>\n  <metadataSection>\n".to_string()
        + &meta("productAnnotationVV", "productVV")
        + &meta("calibrationAnnotationVV", "calibrationVV")
        + &meta("noiseAnnotationVV", "noiseVV")
        + "  </metadataSection>\n  <dataObjectSection>\n"
        + &object("productVV", "s1Level1ProductSchema", &format!("annotation/{STEM}.xml"), "text/xml")
        + &object("calibrationVV", "s1Level1CalibrationSchema", &format!("annotation/calibration/calibration-{STEM}.xml"), "text/xml")
        + &object("noiseVV", "s1Level1NoiseSchema", &format!("annotation/calibration/noise-{STEM}.xml"), "text/xml")
        + &object("measurementVV", "s1Level1MeasurementSchema", &format!("measurement/{STEM}.tiff"), "application/octet-stream")
        + "  </dataObjectSection>\n</xfdu:XFDU>\n"
}

/// The measurement TIFF: uint16 in one-row strips, written by GDAL's GTiff driver, a strip of
/// rows at a time (a full-size product is not held in memory).
fn write_measurement(s: &Synthetic, path: &Path) {
    let driver = DriverManager::get_driver_by_name("GTiff").unwrap();
    let mut options = gdal::cpl::CslStringList::new();
    options.add_name_value("BLOCKYSIZE", "1").unwrap();
    let dataset = driver
        .create_with_band_type_with_options::<u16, _>(path, s.samples, s.lines, 1, &options)
        .unwrap();
    let mut band = dataset.rasterband(1).unwrap();
    for start in (0..s.lines).step_by(1024) {
        let n = 1024.min(s.lines - start);
        let data: Vec<u16> = (start..start + n)
            .into_par_iter()
            .flat_map_iter(|l| (0..s.samples).map(move |p| (s.dn)(l, p)))
            .collect();
        band.write(
            (0, start as isize),
            (s.samples, n),
            &mut Buffer::new((s.samples, n), data),
        )
        .unwrap();
    }
}

/// The product's annotation files: (path inside the SAFE folder, contents).
fn annotation_files(s: &Synthetic) -> Vec<(String, Vec<u8>)> {
    vec![
        ("manifest.safe".into(), manifest_xml().into_bytes()),
        (format!("annotation/{STEM}.xml"), product_xml(s).into_bytes()),
        (
            format!("annotation/calibration/calibration-{STEM}.xml"),
            calibration_xml(s).into_bytes(),
        ),
        (
            format!("annotation/calibration/noise-{STEM}.xml"),
            noise_xml(s).into_bytes(),
        ),
    ]
}

/// Write the product as a `.SAFE` directory under `dir`; returns its path.
pub fn write_safe(dir: &Path, s: &Synthetic) -> PathBuf {
    let root = dir.join(SAFE);
    for (name, bytes) in annotation_files(s) {
        let path = root.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, bytes).unwrap();
    }
    let measurement = root.join(format!("measurement/{STEM}.tiff"));
    std::fs::create_dir_all(measurement.parent().unwrap()).unwrap();
    write_measurement(s, &measurement);
    root
}

/// Add a second polarisation `pol` (say "VH") with its own digital numbers to a product
/// [`write_safe`] wrote at `root`: its annotation, calibration and noise files (the same
/// look-up tables) and its measurement, named as ESA names a dual-polarisation product's
/// (the manifest still lists VV alone; wakelab finds the bands by their annotation files).
pub fn add_polarisation(root: &Path, s: &Synthetic, pol: &str) {
    let stem = STEM.replace("-vv-", &format!("-{}-", pol.to_ascii_lowercase()));
    for (name, bytes) in annotation_files(s).into_iter().skip(1) {
        let text = String::from_utf8(bytes).unwrap().replace(
            "<polarisation>VV</polarisation>",
            &format!("<polarisation>{}</polarisation>", pol.to_ascii_uppercase()),
        );
        let path = root.join(name.replace(STEM, &stem));
        std::fs::write(path, text).unwrap();
    }
    write_measurement(s, &root.join(format!("measurement/{stem}.tiff")));
}

/// Write the product as a `.zip` (the SAFE folder inside, as ESA distributes it), through
/// GDAL's /vsizip/ writer.
pub fn write_zip(dir: &Path, s: &Synthetic) -> PathBuf {
    let zip = dir.join(SAFE.replace(".SAFE", ".zip"));
    let tiff = dir.join("measurement.tmp.tiff");
    write_measurement(s, &tiff);
    let mut files = annotation_files(s);
    files.push((format!("measurement/{STEM}.tiff"), std::fs::read(&tiff).unwrap()));
    std::fs::remove_file(&tiff).unwrap();
    for (name, bytes) in files {
        let inner = std::ffi::CString::new(format!("/vsizip/{}/{SAFE}/{name}", zip.display())).unwrap();
        let mode = std::ffi::CString::new("wb").unwrap();
        // SAFETY: plain C calls on a file handle checked for NULL, closed before the next.
        unsafe {
            let f = gdal_sys::VSIFOpenL(inner.as_ptr(), mode.as_ptr());
            assert!(!f.is_null(), "cannot write {name} into the zip");
            let written = gdal_sys::VSIFWriteL(bytes.as_ptr() as *const std::ffi::c_void, 1, bytes.len(), f);
            assert_eq!(written, bytes.len());
            gdal_sys::VSIFCloseL(f);
        }
    }
    zip
}

/// The expected sigma0 of (line, pixel): (DN^2 - eta) / A^2, eta from the closed forms, the
/// noise-equivalent sigma0 where that is not positive, None on no-data.
pub fn expected_sigma0(s: &Synthetic, l: usize, p: usize, remove_noise: bool) -> Option<f64> {
    let d = (s.dn)(l, p) as f64;
    if d == 0.0 {
        return None;
    }
    let (lf, pf) = (l as f64, p as f64);
    let eta = if !remove_noise {
        0.0
    } else if s.since_2_9 {
        s.noise_range(lf, pf) * s.noise_azimuth(lf, pf)
    } else {
        s.noise_range(lf, pf)
    };
    let a2 = s.gain(lf, pf).powi(2);
    let sigma0 = (d * d - eta) / a2;
    Some(if sigma0 > 0.0 { sigma0 } else { eta / a2 })
}
