//! Where an image's pixels lie on the Earth: an affine geotransform in a CRS, or ground control
//! points (a Sentinel-1 GRD's geolocation grid), or nothing (a bare array). Pixel coordinates
//! are GDAL's: (column, row) from the top-left corner of the top-left pixel, so the centre of
//! pixel (r, c) is (c + 0.5, r + 0.5). Ground coordinates come from GDAL's own transformer
//! (`GDALCreateGenImgProjTransformer2`, what `gdaltransform` runs), so a detection's longitude
//! and latitude are exactly GDAL's for the same pixel.

use gdal::spatial_ref::SpatialRef;
use gdal::{Dataset, DriverManager, GcpRef};
use std::ffi::CString;

/// A ground control point: pixel (column) and line (row) to x, y, z in the frame's CRS.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gcp {
    pub pixel: f64,
    pub line: f64,
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

/// How the pixels are placed.
#[derive(Debug, Clone, PartialEq)]
pub enum Placement {
    /// No georeference.
    None,
    /// GDAL's geotransform (x = t0 + col t1 + row t2, y = t3 + col t4 + row t5) in a CRS (WKT).
    Transform { transform: [f64; 6], wkt: String },
    /// Ground control points in a CRS (WKT), GDAL fitting a polynomial between them.
    Gcps { gcps: Vec<Gcp>, wkt: String },
}

/// An image grid and its placement.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    pub rows: usize,
    pub cols: usize,
    pub placement: Placement,
}

impl Frame {
    /// A grid with no georeference.
    pub fn none((rows, cols): (usize, usize)) -> Self {
        Self {
            rows,
            cols,
            placement: Placement::None,
        }
    }

    /// The placement GDAL reads from a dataset: its geotransform when it has a CRS or a
    /// geotransform other than the identity, else its GCPs, else none.
    pub fn of_dataset(dataset: &Dataset) -> Self {
        let (cols, rows) = dataset.raster_size();
        let wkt = dataset.projection();
        let transform = dataset.geo_transform().ok();
        let identity = [0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        let placement = match transform {
            Some(t) if wkt.is_empty() && t != identity && degrees_like(&t, rows, cols) => Placement::Transform {
                transform: t,
                wkt: SpatialRef::from_epsg(4326).and_then(|s| s.to_wkt()).unwrap_or_default(),
            },
            Some(t) if !wkt.is_empty() || t != identity => Placement::Transform { transform: t, wkt },
            _ => {
                let gcps: Vec<Gcp> = dataset.gcps().iter().map(gcp_of).collect();
                let wkt = gcp_crs(dataset);
                if gcps.is_empty() || wkt.is_empty() {
                    // GCPs in no CRS place nothing (GDAL cannot write them back either)
                    Placement::None
                } else {
                    Placement::Gcps { gcps, wkt }
                }
            }
        };
        Self { rows, cols, placement }
    }

    /// Whether the frame is placed on the Earth: a geotransform or GCPs in a CRS. Without a CRS
    /// (a TIFF whose CRS was stripped, a Sentinel-1 measurement TIFF taken out of its product,
    /// whose geotransform counts pixels) GDAL's transformer would take the coordinates as
    /// longitude and latitude; they are pixel coordinates only, kept for the outputs' grid.
    pub fn is_georeferenced(&self) -> bool {
        match &self.placement {
            Placement::None => false,
            Placement::Transform { wkt, .. } | Placement::Gcps { wkt, .. } => !wkt.trim().is_empty(),
        }
    }

    /// A note where `dataset`, read into this frame, holds a geotransform but no CRS (either
    /// taken as WGS 84 degrees, [`Self::of_dataset`], or not placed on the Earth), or GCPs with
    /// no CRS (not placed).
    pub fn no_crs_note(&self, dataset: &Dataset) -> Option<String> {
        if !dataset.projection().is_empty() {
            return None;
        }
        if self.placement == Placement::None && !dataset.gcps().is_empty() && gcp_crs(dataset).is_empty() {
            return Some(format!(
                "the file's {} ground control points have no CRS: its pixels are not placed on the Earth (no longitude or latitude; its spacing from the file's metadata or --pixel-spacing)",
                dataset.gcps().len()
            ));
        }
        match &self.placement {
            Placement::Transform { transform: t, wkt } if !wkt.is_empty() => Some(format!(
                "the file's geotransform has no CRS; its coordinates lie within longitude's and latitude's ranges with pixels of {:.2e} x {:.2e} degrees: taken as WGS 84 (EPSG:4326)",
                t[1].hypot(t[4]),
                t[2].hypot(t[5])
            )),
            Placement::Transform { .. } => Some(
                "the file's geotransform has no CRS and its coordinates are no longitude and latitude: its pixels are not placed on the Earth (no longitude or latitude; its spacing from the file's metadata or --pixel-spacing)".into(),
            ),
            _ => None,
        }
    }

    /// The frame of a grid whose pixel spans `row_factor` x `col_factor` pixels of this one
    /// (`rows` x `cols` of them).
    pub fn scaled(&self, row_factor: f64, col_factor: f64, (rows, cols): (usize, usize)) -> Self {
        let placement = match &self.placement {
            Placement::None => Placement::None,
            Placement::Transform { transform: t, wkt } => Placement::Transform {
                transform: [
                    t[0],
                    t[1] * col_factor,
                    t[2] * row_factor,
                    t[3],
                    t[4] * col_factor,
                    t[5] * row_factor,
                ],
                wkt: wkt.clone(),
            },
            Placement::Gcps { gcps, wkt } => Placement::Gcps {
                gcps: gcps
                    .iter()
                    .map(|g| Gcp {
                        pixel: g.pixel / col_factor,
                        line: g.line / row_factor,
                        ..*g
                    })
                    .collect(),
                wkt: wkt.clone(),
            },
        };
        Self { rows, cols, placement }
    }

    /// A north-up grid of `spacing` metres whose centre lies at (`latitude`, `longitude`), in
    /// that point's WGS 84 / UTM zone (`epsg`). North up is grid north: it departs from true
    /// north by the meridian convergence (under 3.5 degrees within a zone below 60 degrees of
    /// latitude).
    pub fn utm(
        (latitude, longitude): (f64, f64),
        epsg: u32,
        spacing: f64,
        (rows, cols): (usize, usize),
    ) -> gdal::errors::Result<Self> {
        let mut wgs84 = SpatialRef::from_epsg(4326)?;
        wgs84.set_axis_mapping_strategy(gdal::spatial_ref::AxisMappingStrategy::TraditionalGisOrder);
        let mut utm = SpatialRef::from_epsg(epsg)?;
        utm.set_axis_mapping_strategy(gdal::spatial_ref::AxisMappingStrategy::TraditionalGisOrder);
        let to_utm = gdal::spatial_ref::CoordTransform::new(&wgs84, &utm)?;
        let (mut x, mut y) = ([longitude], [latitude]);
        to_utm.transform_coords(&mut x, &mut y, &mut [])?;
        let (half_w, half_h) = (0.5 * cols as f64 * spacing, 0.5 * rows as f64 * spacing);
        Ok(Self {
            rows,
            cols,
            placement: Placement::Transform {
                transform: [x[0] - half_w, spacing, 0.0, y[0] + half_h, 0.0, -spacing],
                wkt: utm.to_wkt()?,
            },
        })
    }

    /// A grid of `spacing` metres on no place of the Earth: a local engineering CRS in metres,
    /// its origin at the grid's `top_left` (x right, y up).
    pub fn local(top_left: (f64, f64), spacing: f64, (rows, cols): (usize, usize)) -> Self {
        let wkt = r#"LOCAL_CS["wakelab scene grid (metres; not placed on the Earth: set scene.centre)",LOCAL_DATUM["wakelab scene",0],UNIT["metre",1,AUTHORITY["EPSG","9001"]],AXIS["x",EAST],AXIS["y",NORTH]]"#;
        Self {
            rows,
            cols,
            placement: Placement::Transform {
                transform: [top_left.0, spacing, 0.0, top_left.1, 0.0, -spacing],
                wkt: wkt.to_string(),
            },
        }
    }

    /// Give `dataset` (of this frame's size) this placement.
    pub fn apply(&self, dataset: &mut Dataset) -> gdal::errors::Result<()> {
        match &self.placement {
            Placement::None => Ok(()),
            Placement::Transform { transform, wkt } => {
                dataset.set_geo_transform(transform)?;
                if !wkt.is_empty() {
                    dataset.set_projection(wkt)?;
                }
                Ok(())
            }
            Placement::Gcps { gcps, wkt } => {
                let mut srs = SpatialRef::from_wkt(wkt)?;
                // GCPs hold x = longitude, y = latitude whatever the CRS's axis order
                srs.set_axis_mapping_strategy(gdal::spatial_ref::AxisMappingStrategy::TraditionalGisOrder);
                let list = gcps
                    .iter()
                    .enumerate()
                    .map(|(i, g)| gdal::Gcp {
                        id: (i + 1).to_string(),
                        info: String::new(),
                        pixel: g.pixel,
                        line: g.line,
                        x: g.x,
                        y: g.y,
                        z: g.z,
                    })
                    .collect();
                dataset.set_gcps(list, &srs)
            }
        }
    }

    /// Longitude and latitude (degrees, WGS 84) of pixel coordinates (column, row) by GDAL's
    /// transformer; None without a georeference, or where GDAL cannot place the frame on the
    /// Earth (a local engineering CRS) or a point.
    pub fn lonlat(&self, points: &[(f64, f64)]) -> Option<Vec<(f64, f64)>> {
        if !self.is_georeferenced() || points.is_empty() {
            return None;
        }
        let driver = DriverManager::get_driver_by_name("MEM").ok()?;
        let mut dataset = driver
            .create_with_band_type::<u8, _>("", self.cols.max(1), self.rows.max(1), 0)
            .ok()?;
        self.apply(&mut dataset).ok()?;
        let (mut x, mut y): (Vec<f64>, Vec<f64>) = points.iter().copied().unzip();
        let mut z = vec![0.0; points.len()];
        let mut success = vec![0i32; points.len()];
        let option = CString::new("DST_SRS=EPSG:4326").expect("no NUL");
        let mut options = [option.as_ptr() as *mut std::ffi::c_char, std::ptr::null_mut()];
        // SAFETY: the dataset outlives the transformer, which is destroyed before return; the
        // option list is NULL-terminated; the point arrays hold points.len() values each.
        let ok = unsafe {
            let transformer = gdal_sys::GDALCreateGenImgProjTransformer2(
                dataset.c_dataset(),
                std::ptr::null_mut(),
                options.as_mut_ptr(),
            );
            if transformer.is_null() {
                return None;
            }
            let ok = gdal_sys::GDALGenImgProjTransform(
                transformer,
                0,
                points.len() as i32,
                x.as_mut_ptr(),
                y.as_mut_ptr(),
                z.as_mut_ptr(),
                success.as_mut_ptr(),
            );
            gdal_sys::GDALDestroyGenImgProjTransformer(transformer);
            ok
        };
        (ok != 0 && success.iter().all(|&s| s != 0)).then(|| x.into_iter().zip(y).collect())
    }

    /// Ground distance (m) between neighbouring pixels at the image's centre: along a row
    /// (columns) and down a column (rows); None without a place on the Earth.
    pub fn ground_spacing(&self) -> Option<(f64, f64)> {
        let (r, c) = (self.rows as f64 / 2.0, self.cols as f64 / 2.0);
        let p = self.lonlat(&[(c, r), (c + 1.0, r), (c, r + 1.0)])?;
        Some((ground_distance(p[0], p[1]), ground_distance(p[0], p[2])))
    }
}

/// The largest pixel (degrees) a geotransform without a CRS may have to be read as WGS 84
/// longitude and latitude: 0.01 degrees, about 1.1 km, coarser than any SAR product's pixels;
/// a geotransform that counts pixels (steps of 1) is not.
const MAX_DEGREE_PIXEL: f64 = 0.01;

/// Whether a geotransform without a CRS reads as WGS 84 degrees: its four corners within
/// longitude's [-180, 180] and latitude's [-90, 90], its pixels at most [`MAX_DEGREE_PIXEL`]
/// on a side. GDAL's transformer takes a CRS-less geotransform as the target's CRS (degrees
/// here) whatever it holds; files that lost their CRS in EPSG:4326 keep their place so, and
/// one counting pixels is no longer read as 111 km per pixel.
fn degrees_like(t: &[f64; 6], rows: usize, cols: usize) -> bool {
    let pixel = t[1].hypot(t[4]).max(t[2].hypot(t[5]));
    let corners = [
        (0.0, 0.0),
        (cols as f64, 0.0),
        (0.0, rows as f64),
        (cols as f64, rows as f64),
    ];
    pixel > 0.0
        && pixel <= MAX_DEGREE_PIXEL
        && corners.iter().all(|&(c, r)| {
            let (x, y) = (t[0] + c * t[1] + r * t[2], t[3] + c * t[4] + r * t[5]);
            (-180.0..=180.0).contains(&x) && (-90.0..=90.0).contains(&y)
        })
}

/// The CRS (WKT) of `dataset`'s GCPs; empty where they have none.
fn gcp_crs(dataset: &Dataset) -> String {
    dataset.gcp_projection().unwrap_or_default().trim().to_string()
}

fn gcp_of(g: &GcpRef) -> Gcp {
    Gcp {
        pixel: g.pixel(),
        line: g.line(),
        x: g.x(),
        y: g.y(),
        z: g.z(),
    }
}

/// Ground distance (m) between two nearby (longitude, latitude) points on the WGS 84
/// ellipsoid: the latitude difference times the meridian radius of curvature M and the
/// longitude difference times N cos(latitude), N the prime-vertical radius, both at the mean
/// latitude (exact to first order in the separation; Snyder 1987, Eqs. 4-18, 4-20).
pub fn ground_distance(a: (f64, f64), b: (f64, f64)) -> f64 {
    const SEMI_MAJOR: f64 = 6_378_137.0;
    const FLATTENING: f64 = 1.0 / 298.257_223_563;
    let e2 = FLATTENING * (2.0 - FLATTENING);
    let lat = (0.5 * (a.1 + b.1)).to_radians();
    let w = 1.0 - e2 * lat.sin().powi(2);
    let n = SEMI_MAJOR / w.sqrt();
    let m = SEMI_MAJOR * (1.0 - e2) / w.powf(1.5);
    let dy = m * (b.1 - a.1).to_radians();
    let dx = n * lat.cos() * (b.0 - a.0).to_radians();
    dx.hypot(dy)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// UTM zone 33N (EPSG:32633): its central meridian is 15 E, so a point on it at northing
    /// 5,000,000 m lies at 15 E, and 1 km east of it lies 1 km of ground away.
    #[test]
    fn a_utm_frame_is_placed_where_the_projection_puts_it() {
        let wkt = SpatialRef::from_epsg(32633).unwrap().to_wkt().unwrap();
        let frame = Frame {
            rows: 100,
            cols: 100,
            placement: Placement::Transform {
                transform: [500_000.0, 10.0, 0.0, 5_000_000.0, 0.0, -10.0],
                wkt,
            },
        };
        let p = frame.lonlat(&[(0.0, 0.0)]).unwrap()[0];
        assert!((p.0 - 15.0).abs() < 1e-9, "{p:?}");
        // northing 5,000 km on the central meridian: the footpoint latitude of the meridian arc
        // 5,000,000 / 0.9996 m on WGS 84, 45.15348 N (Snyder 1987, Eqs. 3-21, 8-18)
        assert!((p.1 - 45.15348).abs() < 1e-4, "{p:?}");
        let (dx, dy) = frame.ground_spacing().unwrap();
        // 10 m of grid on the central meridian is 10 / k0 = 10 / 0.9996 m of ground
        assert!(
            (dx - 10.0 / 0.9996).abs() < 1e-3 && (dy - 10.0 / 0.9996).abs() < 1e-3,
            "{dx} {dy}"
        );
        let coarse = frame.scaled(4.0, 4.0, (25, 25));
        let q = coarse.lonlat(&[(1.0, 1.0)]).unwrap()[0];
        let r = frame.lonlat(&[(4.0, 4.0)]).unwrap()[0];
        assert!((q.0 - r.0).abs() < 1e-12 && (q.1 - r.1).abs() < 1e-12);
        assert!(Frame::none((5, 5)).lonlat(&[(0.0, 0.0)]).is_none());
    }

    /// The published lengths of a degree on WGS 84 at 45 N: 111,132.09 m of latitude and
    /// 78,846.81 m of longitude (NGA's table), here over one arc-second.
    #[test]
    fn ground_distance_of_an_arc_second() {
        let s = 1.0 / 3600.0;
        let north = ground_distance((10.0, 45.0 - s / 2.0), (10.0, 45.0 + s / 2.0));
        let east = ground_distance((10.0, 45.0), (10.0 + s, 45.0));
        assert!((north - 111_132.09 * s).abs() < 1e-3, "{north}");
        assert!((east - 78_846.81 * s).abs() < 1e-3, "{east}");
    }
}
