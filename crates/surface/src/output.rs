//! The surface stage's files: the scene's fields as NetCDF (CF) and PNG pictures.

use crate::SurfaceScene;
use std::path::{Path, PathBuf};
use wakelab_core::io::netcdf::{write_netcdf, CfLayout, CfVariable};
use wakelab_core::io::picture::{Colormap, FieldPicture};
use wakelab_core::{WakelabConfig, WakelabError};

fn f32s<'a>(values: impl IntoIterator<Item = &'a f64>) -> Vec<f32> {
    values.into_iter().map(|&v| v as f32).collect()
}

/// Write `surface_scene.nc` and the scene pictures into `dir`; returns the files written.
pub fn write_surface_scene(
    dir: &Path,
    config: &WakelabConfig,
    scene: &SurfaceScene,
) -> Result<Vec<PathBuf>, WakelabError> {
    let n = scene.grid.size();
    let mut fields: Vec<(String, &str, String, Vec<f32>, Colormap)> = vec![
        (
            "gamma".into(),
            "1",
            "surfactant concentration relative to the ambient film (Eq. (2.66))".into(),
            f32s(&scene.surfactant),
            Colormap::Sequential,
        ),
        (
            "elevation".into(),
            "m",
            "long-wave sea surface elevation (Eqs. (2.72)-(2.76))".into(),
            f32s(&scene.surface.elevation),
            Colormap::Diverging,
        ),
        (
            "slope_x".into(),
            "1",
            "surface slope d zeta / d x (east)".into(),
            f32s(&scene.surface.slope_x),
            Colormap::Diverging,
        ),
        (
            "slope_y".into(),
            "1",
            "surface slope d zeta / d y (north)".into(),
            f32s(&scene.surface.slope_y),
            Colormap::Diverging,
        ),
        (
            "dT".into(),
            "K",
            "sea surface temperature perturbation from the wake".into(),
            f32s(&scene.temperature_anomaly),
            Colormap::Diverging,
        ),
    ];
    if let Some(k) = &scene.kelvin {
        fields.push((
            "kelvin_elevation".into(),
            "m",
            "elevation of the ship's Kelvin waves (thin-ship theory), part of elevation".into(),
            f32s(&k.elevation),
            Colormap::Diverging,
        ));
    }
    for b in &scene.bragg {
        fields.push((
            format!("modulation_{}", b.band.name()),
            "1",
            format!(
                "N/N0 of the {}-band Bragg waves, k = {:.1} rad/m (Eq. (2.67))",
                b.band.name(),
                b.wavenumber
            ),
            f32s(&b.modulation),
            Colormap::Sequential,
        ));
    }
    let mut vars = vec![
        CfVariable::new("x", &["x"], "m", "easting from the ship's stern").axis("X"),
        CfVariable::new("y", &["y"], "m", "northing from the ship's stern").axis("Y"),
    ];
    vars.extend(
        fields
            .iter()
            .map(|(name, units, long, _, _)| CfVariable::new(name, &["y", "x"], units, long)),
    );
    let mut global = vec![
        ("title".to_string(), "wakelab sea surface of one scene".to_string()),
        ("incidence_deg".into(), config.platform.incidence.to_string()),
        ("look_direction_deg".into(), config.platform.look_direction.to_string()),
        ("heading_deg".into(), config.scene.heading.to_string()),
        ("seed".into(), config.seed.to_string()),
        ("wakelab_config".into(), config.to_toml_string()),
    ];
    for b in &scene.bragg {
        global.push((
            format!("bragg_wavenumber_{}", b.band.name()),
            format!("{:.4}", b.wavenumber),
        ));
    }
    let layout = CfLayout {
        dims: vec![("y".into(), n), ("x".into(), n)],
        record_dim: None,
        variables: vars,
        global,
    };
    let (x, y) = (f32s(&scene.grid.x), f32s(&scene.grid.y));
    let mut data: Vec<(&str, &[f32])> = vec![("x", &x), ("y", &y)];
    data.extend(
        fields
            .iter()
            .map(|(name, _, _, values, _)| (name.as_str(), values.as_slice())),
    );
    let mut files = vec![write_netcdf(&dir.join("surface_scene.nc"), &layout, &data)?];
    if config.output.pictures {
        let caption = format!(
            "x {:.0}..{:.0} m east, y {:.0}..{:.0} m north of the stern; ship heading {:.0} deg",
            scene.grid.x[0],
            scene.grid.x[n - 1],
            scene.grid.y[n - 1],
            scene.grid.y[0],
            scene.grid.heading.to_degrees().rem_euclid(360.0)
        );
        for (name, units, long, values, colormap) in &fields {
            if name.starts_with("slope") {
                continue;
            }
            let pic = FieldPicture {
                values,
                rows: n,
                cols: n,
                title: format!("scene {name}"),
                units: units.to_string(),
                colormap: *colormap,
                size: (512, 512),
                caption: format!("{long}; {caption}"),
            };
            let path = dir.join(format!("scene_{name}.png"));
            pic.write_png(&path)?;
            files.push(path);
        }
    }
    Ok(files)
}
