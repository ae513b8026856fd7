//! The hydro stage's files: cross-sections and surface slices as they are computed (NetCDF,
//! streamed one record at a time so memory stays bounded), the surface map x = U_ship t
//! (NetCDF), the IDP scalars (JSON) and PNG pictures of the surface wake and cross-sections.
//!
//! Every file is written to a temporary name and renamed when complete, so a failed run leaves
//! no half-written output.

use crate::slices::{CrossSection, SliceField, SurfaceMap, SLICE_FIELDS};
use crate::{simulate_wake_with, WakeEvent, WakeSlices};
use std::path::{Path, PathBuf};
use wakelab_core::io::netcdf::{read_f32, write_netcdf, CfLayout, CfVariable, CfWriter};
use wakelab_core::io::picture::{Colormap, FieldPicture};
use wakelab_core::io::write_atomically;
use wakelab_core::{CrossGrid, WakelabConfig, WakelabError};

/// Files written by [`run_hydro_stage`].
#[derive(Debug, Clone, Default)]
pub struct HydroOutputs {
    pub files: Vec<PathBuf>,
    pub steps: usize,
}

fn global_attributes(config: &WakelabConfig, title: &str) -> Vec<(String, String)> {
    vec![
        ("title".into(), title.into()),
        (
            "source".into(),
            format!("wakelab {} 2D+t RANS wake solver", env!("CARGO_PKG_VERSION")),
        ),
        ("ship".into(), config.ship.name.clone()),
        ("preset".into(), config.preset.name().into()),
        ("wakelab_config".into(), config.to_toml_string()),
    ]
}

fn field_variables(dims: &[&str]) -> Vec<CfVariable> {
    SliceField::ALL
        .iter()
        .map(|f| {
            let (name, units, long) = f.cf();
            let v = CfVariable::new(name, dims, units, long);
            match f.standard_name() {
                Some(s) => v.standard_name(s),
                None => v,
            }
        })
        .collect()
}

/// Time is a duration since the initial data plane (CF-1.8 Sec. 4.4, units without "since"): a
/// simulation has no calendar date, and xarray decodes it as `timedelta64`.
fn time_var() -> CfVariable {
    CfVariable::duration("time", &["time"], "time since the initial data plane")
        .axis("T")
        .standard_name("time")
}

fn y_var() -> CfVariable {
    CfVariable::new(
        "y",
        &["y"],
        "m",
        "cross-track distance from the ship's track, positive to port",
    )
    .axis("Y")
}

fn z_var() -> CfVariable {
    CfVariable::new("z", &["z"], "m", "height above the mean sea surface")
        .axis("Z")
        .positive("up")
        .standard_name("height")
}

fn to_f32(v: &[f64]) -> Vec<f32> {
    v.iter().map(|&x| x as f32).collect()
}

/// A NetCDF writer of `layout` at `path` with its `coordinates` written.
fn started_writer(path: &Path, layout: &CfLayout, coordinates: &[(&str, &Vec<f64>)]) -> Result<CfWriter, WakelabError> {
    let mut writer = CfWriter::create(path, layout)?;
    for (name, values) in coordinates {
        writer.put(name, &to_f32(values))?;
    }
    Ok(writer)
}

/// Run the hydro stage of `config` and write its files into `dir`; `progress` is called after
/// every step with (simulated time, steps) and may cancel the run by returning an error, which
/// leaves no NetCDF file behind.
pub fn run_hydro_stage(
    config: &WakelabConfig,
    dir: &Path,
    progress: &mut dyn FnMut(f64, usize) -> Result<(), WakelabError>,
) -> Result<(WakeSlices, HydroOutputs), WakelabError> {
    std::fs::create_dir_all(dir).map_err(|e| WakelabError::io(dir, e))?;
    let grid = CrossGrid::new(&config.grid);
    let t = &config.time;
    let count = |interval: f64| {
        let n = (t.duration / interval + 1e-9).floor() as usize;
        n + 1 + usize::from(t.duration - n as f64 * interval > 1e-9)
    };
    let n_sections = count(t.output_interval);

    let mut outputs = HydroOutputs::default();
    let run = {
        let mut sec_vars = vec![time_var(), z_var(), y_var()];
        sec_vars.extend(field_variables(&["time", "y", "z"]));
        let sec_layout = CfLayout {
            dims: vec![("y".into(), grid.ny()), ("z".into(), grid.nz())],
            record_dim: Some("time".into()),
            variables: sec_vars,
            global: global_attributes(config, "wakelab ship wake cross-sections (2D+t)"),
        };
        let mut surf_vars = vec![time_var(), y_var()];
        surf_vars.extend(field_variables(&["time", "y"]));
        let surf_layout = CfLayout {
            dims: vec![("y".into(), grid.ny())],
            record_dim: Some("time".into()),
            variables: surf_vars,
            global: global_attributes(config, "wakelab ship wake surface slices (top cell, 2D+t)"),
        };
        let coordinates = [("y", &grid.y_centres), ("z", &grid.z_centres)];
        let mut sec_w = started_writer(&dir.join("wake_sections.nc"), &sec_layout, &coordinates)?;
        let mut surf_w = started_writer(&dir.join("wake_surface.nc"), &surf_layout, &coordinates[..1])?;
        let (mut sec_i, mut surf_i) = (0usize, 0usize);
        let mut picked: Vec<CrossSection> = Vec::new();
        let pick = [0, n_sections / 2, n_sections - 1];
        let run = simulate_wake_with(config, &mut |e| {
            match e {
                WakeEvent::Progress { time, steps, .. } => progress(time, steps)?,
                WakeEvent::Section(s) => {
                    write_record(&mut sec_w, sec_i, s.time, &s.fields)?;
                    if pick.contains(&sec_i) && config.output.pictures {
                        picked.push(s.clone());
                    }
                    sec_i += 1;
                }
                WakeEvent::Surface(s) => {
                    write_record(&mut surf_w, surf_i, s.time, &s.fields)?;
                    surf_i += 1;
                }
            }
            Ok(())
        })?;
        outputs.files.push(sec_w.commit()?);
        outputs.files.push(surf_w.commit()?);
        if config.output.pictures {
            for s in &picked {
                outputs.files.extend(write_section_pictures(dir, &grid, s)?);
            }
        }
        run
    };

    let map = run.surface_map(config, config.output.map_dx);
    outputs.files.push(write_surface_map(dir, config, &map)?);
    if config.output.pictures {
        outputs.files.extend(write_surface_pictures(dir, &map)?);
    }
    let idp = serde_json::to_string_pretty(&run.idp).expect("serialisable");
    outputs
        .files
        .push(write_atomically(dir.join("idp.json"), idp.as_bytes())?);
    outputs.steps = run.steps;
    Ok((run, outputs))
}

fn write_record(w: &mut CfWriter, i: usize, time: f64, fields: &[Vec<f32>]) -> Result<(), WakelabError> {
    w.put_duration("time", i, time)?;
    for ((name, _, _), data) in SLICE_FIELDS.iter().zip(fields) {
        w.put_record(name, i, data)?;
    }
    Ok(())
}

/// Write the (x, y) surface map as NetCDF.
pub fn write_surface_map(dir: &Path, config: &WakelabConfig, map: &SurfaceMap) -> Result<PathBuf, WakelabError> {
    let mut vars = vec![
        CfVariable::new(
            "x",
            &["x"],
            "m",
            "distance behind the stern (x = U_ship t + x_IDP, Eq. (2.24))",
        )
        .axis("X"),
        y_var(),
    ];
    vars.extend(field_variables(&["x", "y"]));
    let layout = CfLayout {
        dims: vec![("x".into(), map.x.len()), ("y".into(), map.y.len())],
        record_dim: None,
        variables: vars,
        global: global_attributes(config, "wakelab surface wake map"),
    };
    let (x, y) = (to_f32(&map.x), to_f32(&map.y));
    let mut data: Vec<(&str, &[f32])> = vec![("x", &x), ("y", &y)];
    data.extend(
        SLICE_FIELDS
            .iter()
            .zip(&map.fields)
            .map(|((n, _, _), d)| (*n, d.as_slice())),
    );
    write_netcdf(&dir.join("surface_map.nc"), &layout, &data)
}

/// Fields drawn in pictures: (name, diverging colour map).
const PICTURED: [(SliceField, bool); 5] = [
    (SliceField::U, true),
    (SliceField::V, true),
    (SliceField::K, false),
    (SliceField::DT, true),
    (SliceField::NuT, false),
];

/// Half-width (m) of the strip drawn in surface pictures.
const SURFACE_WINDOW: f64 = 250.0;

/// Pictures of the surface map over the central strip, x along the picture's width.
pub fn write_surface_pictures(dir: &Path, map: &SurfaceMap) -> Result<Vec<PathBuf>, WakelabError> {
    let rows = map.x.len();
    // picture rows: y from port (top) to starboard (bottom)
    let cols: Vec<usize> = (0..map.y.len())
        .rev()
        .filter(|&c| map.y[c].abs() <= SURFACE_WINDOW)
        .collect();
    let (y_lo, y_hi) = (map.y[cols[cols.len() - 1]], map.y[cols[0]]);
    let mut files = Vec::new();
    for (field, diverging) in PICTURED {
        let i = field.index();
        let src = &map.fields[i];
        let mut t = Vec::with_capacity(rows * cols.len());
        for &c in &cols {
            t.extend((0..rows).map(|r| src[r * map.y.len() + c]));
        }
        let (name, units, long) = field.cf();
        let pic = FieldPicture {
            values: &t,
            rows: cols.len(),
            cols: rows,
            title: format!("surface {name}"),
            units: units.into(),
            colormap: Colormap::for_field(diverging),
            size: (1200, 300),
            caption: format!(
                "{long}; x {:.0}..{:.0} m behind the stern (left to right); y {y_lo:.0}..{y_hi:.0} m (port at top)",
                map.x[0],
                map.x[rows - 1],
            ),
        };
        let path = dir.join(format!("surface_{name}.png"));
        pic.write_png(&path)?;
        files.push(path);
    }
    Ok(files)
}

/// Half-width and depth (m) of the near-wake window drawn in cross-section pictures.
const SECTION_WINDOW: (f64, f64) = (200.0, 60.0);

/// Pictures of one cross-section, over the near-wake window of the core.
pub fn write_section_pictures(dir: &Path, grid: &CrossGrid, s: &CrossSection) -> Result<Vec<PathBuf>, WakelabError> {
    let nz = grid.nz();
    let cols: Vec<usize> = grid
        .core
        .clone()
        .filter(|&j| grid.y_centres[j].abs() <= SECTION_WINDOW.0)
        .collect();
    let rows: Vec<usize> = (0..nz).filter(|&k| -grid.z_centres[k] <= SECTION_WINDOW.1).collect();
    let (y0, y1) = (grid.y_faces[cols[0]], grid.y_faces[cols[cols.len() - 1] + 1]);
    let depth = (rows.len() as f64 * grid.dz).min(grid.depth);
    let mut files = Vec::new();
    for (field, diverging) in PICTURED {
        let i = field.index();
        let src = &s.fields[i];
        let mut t = Vec::with_capacity(rows.len() * cols.len());
        for &k in &rows {
            t.extend(cols.iter().map(|&j| src[j * nz + k]));
        }
        let (name, units, long) = field.cf();
        let pic = FieldPicture {
            values: &t,
            rows: rows.len(),
            cols: cols.len(),
            title: format!("{name} at t = {:.0} s", s.time),
            units: units.into(),
            colormap: Colormap::for_field(diverging),
            size: (1000, 300),
            caption: format!("{long}; y {y0:.0}..{y1:.0} m (starboard to port), depth 0..{depth:.0} m"),
        };
        let path = dir.join(format!("section_{name}_t{:05.0}.png", s.time));
        pic.write_png(&path)?;
        files.push(path);
    }
    Ok(files)
}

/// Write the IDP fields on the grid (NetCDF) and pictures of U_0 and k_0.
pub fn write_idp_fields(dir: &Path, config: &WakelabConfig) -> Result<Vec<PathBuf>, WakelabError> {
    let grid = CrossGrid::new(&config.grid);
    let idp = crate::initial_data_plane(config);
    let names = [
        (
            "U0",
            "m s-1",
            "IDP axial wake velocity relative to the ship, Eq. (2.26)",
        ),
        ("V0", "m s-1", "IDP cross-track swirl velocity, Eq. (2.51)"),
        ("W0", "m s-1", "IDP vertical swirl velocity, Eq. (2.51)"),
        ("k0", "m2 s-2", "IDP turbulence kinetic energy"),
        ("eps0", "m2 s-3", "IDP dissipation rate"),
    ];
    let (ny, nz) = (grid.ny(), grid.nz());
    let mut data = vec![Vec::with_capacity(ny * nz); names.len()];
    for &y in &grid.y_centres {
        for &z in &grid.z_centres {
            let p = idp.at(y, -z);
            for (d, v) in data.iter_mut().zip([p.u0, p.v, p.w, p.k, p.eps]) {
                d.push(v as f32);
            }
        }
    }
    let mut vars = vec![z_var(), y_var()];
    vars.extend(names.iter().map(|(n, u, l)| CfVariable::new(n, &["y", "z"], u, l)));
    let layout = CfLayout {
        dims: vec![("y".into(), ny), ("z".into(), nz)],
        record_dim: None,
        variables: vars,
        global: global_attributes(config, "wakelab initial data plane"),
    };
    let (yc, zc) = (to_f32(&grid.y_centres), to_f32(&grid.z_centres));
    let mut columns: Vec<(&str, &[f32])> = vec![("y", &yc), ("z", &zc)];
    columns.extend(names.iter().zip(&data).map(|((n, _, _), d)| (*n, d.as_slice())));
    let mut files = vec![write_netcdf(&dir.join("idp.nc"), &layout, &columns)?];
    // pictures of the near field: 60 m either side, top 20 m
    let (ys, zs): (Vec<usize>, Vec<usize>) = (
        (0..ny).filter(|&j| grid.y_centres[j].abs() <= 30.0).collect(),
        (0..nz).filter(|&k| grid.z_centres[k] >= -15.0).collect(),
    );
    for (idx, diverging) in [(0usize, true), (3, false)] {
        let mut t = Vec::with_capacity(ys.len() * zs.len());
        for &k in &zs {
            for &j in &ys {
                t.push(data[idx][j * nz + k]);
            }
        }
        let (n, u, l) = names[idx];
        let pic = FieldPicture {
            values: &t,
            rows: zs.len(),
            cols: ys.len(),
            title: format!("initial data plane {n}"),
            units: u.into(),
            colormap: Colormap::for_field(diverging),
            size: (800, 400),
            caption: format!("{l}; y -30..30 m (starboard to port), depth 0..15 m"),
        };
        let path = dir.join(format!("idp_{n}.png"));
        pic.write_png(&path)?;
        files.push(path);
    }
    Ok(files)
}

/// Read a surface map written by [`write_surface_map`].
pub fn read_surface_map(path: &Path) -> Result<SurfaceMap, WakelabError> {
    let to64 = |v: Vec<f32>| v.into_iter().map(f64::from).collect::<Vec<f64>>();
    let x = to64(read_f32(path, "x")?);
    let y = to64(read_f32(path, "y")?);
    let fields = SLICE_FIELDS
        .iter()
        .map(|(name, _, _)| read_f32(path, name))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(SurfaceMap { x, y, fields })
}
