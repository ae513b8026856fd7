//! The detectors shipped in the binary, for `wakelab detect IMAGE` without `--model`: the
//! transfer study's C-band classifiers (`wakelab run --study transfer`, [`crate::transfer`]),
//! trained on domain-randomised scenes for real images, their thresholds set for 1 false alarm
//! per 1,000 km^2 of simulated open sea. `models/README.md` says which commit and command made
//! them and their SHA-256; a test holds the bytes to those hashes.

use anyhow::{anyhow, Result};
use std::path::{Path, PathBuf};
use wakelab_learn::store::{detector_info, ModelInfo};
use wakelab_products::PixelSpacing;
use wakelab_schema::band::Band;

/// A detector held in the binary.
pub struct ShippedDetector {
    /// Its file name in `models/`.
    pub name: &'static str,
    /// The detector file's bytes.
    pub bytes: &'static [u8],
}

impl ShippedDetector {
    /// What the file's metadata says (band, window, pixel spacing, threshold).
    pub fn info(&self) -> Result<ModelInfo> {
        Ok(detector_info(self.bytes, &self.path())?)
    }

    /// How outputs and errors name it (`shipped:<file>`).
    pub fn path(&self) -> PathBuf {
        PathBuf::from(format!("shipped:{}", self.name))
    }
}

/// The shipped detectors, finest pixels first: 64-pixel windows of 1.28 km at 20 m and of
/// 2.56 km at 40 m (the transfer study's two footprints; 1.28 km found more wakes at the same
/// alarm rate, docs/results.md).
pub const SHIPPED: [ShippedDetector; 2] = [
    ShippedDetector {
        name: "C_transfer_1280m.safetensors",
        bytes: include_bytes!("../../../models/C_transfer_1280m.safetensors"),
    },
    ShippedDetector {
        name: "C_transfer_2560m.safetensors",
        bytes: include_bytes!("../../../models/C_transfer_2560m.safetensors"),
    },
];

/// The band the shipped detectors were trained for.
pub const SHIPPED_BAND: Band = Band::C;

/// The shipped detector for an image of `spacing` (its ground pixel spacing; `image` names it in
/// errors): the finest whose pixels are no finer than the image's beyond the 25 % a scan
/// accepts ([`crate::product_scan`]), so that the image is averaged down to the detector's
/// spacing and never interpolated up to it.
pub fn choose(image: &Path, spacing: Option<&PixelSpacing>) -> Result<&'static ShippedDetector> {
    let spacing = spacing.ok_or_else(|| {
        anyhow!(
            "{}: the image states no pixel spacing, which picks the shipped detector's footprint: pass \
             --pixel-spacing M (its ground spacing in metres), or --model FILE",
            image.display()
        )
    })?;
    let coarsest = spacing.rows.max(spacing.columns);
    let mut trained = Vec::new();
    for shipped in &SHIPPED {
        let detector_spacing = shipped.info()?.pixel_spacing.unwrap_or(f64::NAN);
        if coarsest <= detector_spacing * 1.25 {
            return Ok(shipped);
        }
        trained.push(detector_spacing);
    }
    let largest = trained.iter().cloned().fold(f64::NAN, f64::max);
    Err(anyhow!(
        "{}: IMAGE pixel spacing {:.1} x {:.1} m is coarser than the shipped detectors' (at most {:.0} m, their {} m \
         plus 25 %): pass --model FILE with a detector trained at the image's spacing",
        image.display(),
        spacing.rows,
        spacing.columns,
        largest * 1.25,
        trained.iter().map(|s| format!("{s}")).collect::<Vec<_>>().join(" and ")
    ))
}

/// What `detect` notes of the shipped detector it chose.
pub fn shipped_note(shipped: &ShippedDetector, info: &ModelInfo) -> String {
    let spacing = info.pixel_spacing.unwrap_or(f64::NAN);
    format!(
        "no --model: the shipped detector {} ({} windows of {:.2} km at {spacing} m, trained by `wakelab run --study \
         transfer`; models/README.md)",
        shipped.name,
        info.architecture,
        info.input_size as f64 * spacing / 1000.0
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use sha2::{Digest, Sha256};
    use wakelab_products::SpacingSource;

    fn spacing(m: f64) -> PixelSpacing {
        PixelSpacing {
            rows: m,
            columns: m,
            source: SpacingSource::User,
        }
    }

    /// The shipped bytes are the ones `models/README.md` names by hash, and their metadata
    /// says what the embedded transfer study makes: C band, 64-pixel windows at 20 and 40 m,
    /// thresholds set for 1 alarm per 1,000 km^2 on open sea, its input and head.
    #[test]
    fn the_shipped_detectors_are_the_ones_the_readme_names() {
        let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/README.md")).unwrap();
        for (shipped, metres) in SHIPPED.iter().zip([20.0, 40.0]) {
            let hash: String = Sha256::digest(shipped.bytes)
                .iter()
                .map(|b| format!("{b:02x}"))
                .collect();
            let line = readme.lines().find(|l| l.contains(shipped.name)).unwrap();
            assert!(
                line.contains(&hash),
                "{}: SHA-256 {hash} not on its README line {line:?}",
                shipped.name
            );
            let info = shipped.info().unwrap();
            assert_eq!(info.single_band().unwrap(), SHIPPED_BAND);
            assert_eq!((info.input_size, info.pixel_spacing), (64, Some(metres)));
            let calibration = info.calibration.unwrap();
            assert_eq!(calibration.false_alarms_per_1000_km2, Some(1.0));
            assert!(info.threshold > 0.0 && info.threshold < 1.0);
            // what the embedded transfer study trains: line sums, pooled
            let study =
                wakelab_dataset::study::Study::from_toml_str(wakelab_dataset::study::TRANSFER_STUDY, "transfer")
                    .unwrap();
            let plan = study.transfer.unwrap();
            assert_eq!(
                (info.input_form, info.head),
                (plan.input, plan.head),
                "{}",
                shipped.name
            );
        }
    }

    /// Each shipped detector's PyTorch export (for `python/wakelab_torch.py`) is in `models/`
    /// with the hash the README names, and says what the detector says: the same metadata but
    /// the layout.
    #[test]
    fn the_shipped_exports_are_the_detectors_in_pytorch_layout() {
        let models = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../models"));
        let readme = std::fs::read_to_string(models.join("README.md")).unwrap();
        for shipped in SHIPPED {
            let name = shipped.name.replace(".safetensors", ".pytorch.safetensors");
            let export = models.join(&name);
            let bytes = std::fs::read(&export).unwrap();
            let hash: String = Sha256::digest(&bytes).iter().map(|b| format!("{b:02x}")).collect();
            let line = readme.lines().find(|l| l.contains(&name)).unwrap();
            assert!(
                line.contains(&hash),
                "{name}: SHA-256 {hash} not on its README line {line:?}"
            );
            let mut theirs = wakelab_learn::store::read_metadata(&export).unwrap();
            let mut ours = wakelab_learn::store::read_metadata(&models.join(shipped.name)).unwrap();
            assert_eq!(theirs.remove("wakelab.layout").as_deref(), Some("pytorch"), "{name}");
            assert_eq!(
                ours.remove("wakelab.layout").as_deref(),
                Some("burn"),
                "{}",
                shipped.name
            );
            assert_eq!(theirs, ours, "{name}");
        }
    }

    /// An image's spacing picks the finest detector it can be averaged down to.
    #[test]
    fn the_spacing_picks_the_footprint() {
        let image = Path::new("scene.tif");
        let name = |m: f64| choose(image, Some(&spacing(m))).map(|s| s.name);
        assert_eq!(name(10.0).unwrap(), "C_transfer_1280m.safetensors");
        assert_eq!(name(25.0).unwrap(), "C_transfer_1280m.safetensors");
        assert_eq!(name(40.0).unwrap(), "C_transfer_2560m.safetensors");
        let e = name(60.0).unwrap_err().to_string();
        assert!(
            e.contains("60.0 x 60.0 m") && e.contains("at most 50 m") && e.contains("--model"),
            "{e}"
        );
        let e = choose(image, None).map(|s| s.name).unwrap_err().to_string();
        assert!(e.contains("--pixel-spacing"), "{e}");
    }
}
