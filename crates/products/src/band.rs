//! The band an input was imaged in, where the input says so: a detector trained on one band
//! scores another band's image without meaning (a C-band detector gave 0.94 on an LWIR image).

use crate::ProductMeta;
use std::path::Path;
use wakelab_schema::band::Band;

/// GeoTIFF metadata item naming the band of a wakelab-written image.
pub const BAND_ITEM: &str = "WAKELAB_BAND";

/// The band of a mission's SAR (None for a mission wakelab does not know).
pub fn mission_band(mission: &str) -> Option<Band> {
    let m = mission.trim().to_ascii_uppercase();
    let any = |prefixes: &[&str]| prefixes.iter().any(|p| m.starts_with(p));
    if any(&["S1", "SENTINEL-1", "SENTINEL1", "RS2", "RADARSAT", "RCM"]) {
        Some(Band::C)
    } else if any(&[
        "TSX", "TDX", "TERRASAR", "TANDEM", "PAZ", "CSK", "CSG", "COSMO", "ICEYE", "CAPELLA",
    ]) {
        Some(Band::X)
    } else {
        None
    }
}

/// The band `path` was imaged in and how that is known: the file's metadata, its mission, or the
/// names wakelab gives its own images (a dataset's `X.npy`, a scene's `sar_C_vv.tif` and
/// `ir_lwir_brightness_temperature.tif`). None where the input does not say.
pub fn imaged_band(path: &Path, meta: &ProductMeta) -> Option<(Band, String)> {
    if let Some(mission) = &meta.mission {
        if let Some(band) = mission_band(mission) {
            return Some((band, format!("its mission, {mission}")));
        }
    }
    if let Some(band) = meta.band {
        return Some((band, format!("its metadata ({BAND_ITEM})")));
    }
    let stem = crate::stem_of(path);
    let parse = |token: &str| token.to_ascii_uppercase().parse::<Band>().ok();
    let named = match stem.split('_').collect::<Vec<_>>().as_slice() {
        [band] => parse(band),
        ["sar" | "ir", band, ..] => parse(band),
        _ => None,
    };
    named.map(|band| (band, format!("its name, {stem} (as wakelab names its images)")))
}

/// The band of the input at `path` before reading its pixels, from what names it: a Sentinel-1
/// SAFE (C), a TerraSAR-X product (X), an HDF5 file's `Mission_ID`, a raster's `WAKELAB_BAND`
/// or `WAKELAB_MISSION` metadata, or wakelab's own names. None where nothing says.
pub fn peek(path: &Path) -> Option<(Band, String)> {
    use gdal::Metadata;
    if matches!(crate::sentinel1::SafeLocation::find(path), Ok(Some(_))) {
        return Some((Band::C, "its format, a Sentinel-1 SAFE".into()));
    }
    if crate::terrasar::find(path).is_some() {
        return Some((Band::X, "its format, a TerraSAR-X product".into()));
    }
    let mut meta = ProductMeta::default();
    if path.is_file() || crate::is_subdataset(path) {
        crate::quiet_gdal();
        if let Ok(dataset) = gdal::Dataset::open(path) {
            meta.mission = ["WAKELAB_MISSION", "Mission_ID", "MISSION_ID", "MISSION"]
                .iter()
                .find_map(|key| dataset.metadata_item(key, ""));
            meta.band = dataset.metadata_item(BAND_ITEM, "").and_then(|b| b.trim().parse().ok());
        }
    }
    imaged_band(path, &meta)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn named(name: &str) -> Option<Band> {
        imaged_band(Path::new(name), &ProductMeta::default()).map(|(b, _)| b)
    }

    #[test]
    fn missions_and_wakelab_names_say_the_band() {
        assert_eq!(mission_band("S1A"), Some(Band::C));
        assert_eq!(mission_band("TSX-1"), Some(Band::X));
        assert_eq!(mission_band("CSK"), Some(Band::X));
        assert_eq!(mission_band("ALOS-2"), None);
        assert_eq!(named("scenes/000001-w/LWIR.npy"), Some(Band::Lwir));
        assert_eq!(named("x.npy"), Some(Band::X));
        assert_eq!(named("out/sar_C_vv.tif"), Some(Band::C));
        assert_eq!(named("out/ir_mwir_radiance.tif"), Some(Band::Mwir));
        // a user's own names say nothing
        assert_eq!(named("harbour_c_band.tif"), None);
        assert_eq!(named("image.tif"), None);
        let meta = ProductMeta {
            mission: Some("S1B".into()),
            ..Default::default()
        };
        let (band, how) = imaged_band(Path::new("LWIR.tif"), &meta).unwrap();
        assert_eq!((band, how.as_str()), (Band::C, "its mission, S1B"));
    }
}
