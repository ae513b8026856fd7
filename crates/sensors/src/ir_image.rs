//! One infrared band's image of a scene (Algorithm 1): every facet's radiance (Eq. (3.5)) from
//! the tabulated terms of [`IrView`], then the imager's point-spread function and noise.

use crate::image_formation::{form_ir_image, IrFormation};
use crate::ir::{radiance_table, FacetGeometry, IrBand, IrView, RadianceTerms};
use crate::planck::{band_radiance, brightness_temperature};
use ndarray::Array2;
use serde::Serialize;
use wakelab_core::WakelabConfig;
use wakelab_surface::SurfaceScene;

/// One band's IR image: radiance and brightness temperature.
#[derive(Debug, Clone)]
pub struct IrImage {
    pub band: IrBand,
    /// Band radiance at the sensor (W m^-2 sr^-1), (rows, cols).
    pub radiance: Array2<f64>,
    /// Brightness temperature of that radiance (K), as the imager records it: with its noise
    /// and point-spread function when `ir.noise` or `ir.resolution` ask (the radiance is the
    /// scene's own).
    pub brightness_temperature: Array2<f64>,
    pub info: IrInfo,
}

/// Scalars of an IR image, for its metadata.
#[derive(Debug, Clone, Serialize)]
pub struct IrInfo {
    pub band: &'static str,
    pub wavelength_range_um: (f64, f64),
    pub incidence_deg: f64,
    pub look_direction_deg: f64,
    pub sun_elevation_deg: f64,
    pub sun_azimuth_deg: f64,
    pub refractive_index: (f64, f64),
    pub sea_surface_temperature_k: f64,
    /// The flat, undisturbed sea's terms.
    pub flat_sea: RadianceTerms,
    /// The imager's NETD when its noise is on.
    pub netd_k: Option<f64>,
}

/// Render one IR band of `scene` (Algorithm 1; for both bands, [`IrScene`] shares their work).
pub fn render_ir(config: &WakelabConfig, scene: &SurfaceScene, band: IrBand) -> IrImage {
    IrScene::new(config, scene).render(band)
}

/// A scene as the infrared imager sees it in every band: the bands share every facet's
/// band-free geometry (see [`IrView::geometry`]).
pub type IrScene<'a> = crate::SensorScene<'a, Array2<FacetGeometry>>;

impl IrScene<'_> {
    /// One band's image.
    pub fn render(&self, band: IrBand) -> IrImage {
        let (config, scene) = (self.config, self.scene);
        let view = IrView::new(config, band);
        let geometry = self.shared.get_or_init(|| {
            let surface = &scene.surface;
            ndarray::Zip::from(&surface.slope_x)
                .and(&surface.slope_y)
                .par_map_collect(|&sx, &sy| {
                    // the image's (east, north) gradient in the heading frame of the view
                    let (gx, gy) = scene.grid.heading_frame(sx, sy);
                    view.geometry(gx, gy)
                })
        });
        let t_surface = config.environment.temperature.at_depth(0.0) + 273.15;
        let (dmin, dmax) = scene
            .temperature_anomaly
            .iter()
            .fold((0.0f64, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
        let table = radiance_table(band, t_surface + dmin - 1.0, t_surface + dmax + 1.0);
        let (lo, hi) = band.range();
        // reflectance and sky radiance tabulated finely in the cosines of their angles (within
        // 1e-6 of the radiance: `tabulated_facets_match_the_exact_ones`); the sea's radiance from
        // the temperature table
        let (reflectance, sky) = view.tables();
        let mut radiance = ndarray::Zip::from(geometry)
            .and(&scene.temperature_anomaly)
            .par_map_collect(|g, &dt| {
                view.terms(g, table.at(t_surface + dt), |c| reflectance.at(c), |c| sky.at(c))
                    .total()
            });
        if let Some(cover) = scene.kelvin.as_ref().and_then(|k| k.hull_cover.as_ref()) {
            // the hull's sides: a grey body at its own temperature reflecting the horizon's sky
            let k = &config.kelvin;
            let hull = k.hull_emissivity * band_radiance(lo, hi, t_surface + k.hull_temperature_excess)
                + (1.0 - k.hull_emissivity) * band_radiance(lo, hi, config.ir.sky_horizon_temperature);
            radiance.zip_mut_with(cover, |r, &c| *r = (1.0 - c) * *r + c * hull);
        }
        // the inverse on a table over the image's own span of temperatures (a short search)
        let (r_min, r_max) = radiance
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &r| (a.min(r), b.max(r)));
        let kelvin = |r: f64| brightness_temperature(lo, hi, r).clamp(150.0, 400.0);
        let bt_table = radiance_table(
            band,
            (kelvin(r_min) - 0.05).max(150.0),
            (kelvin(r_max) + 0.05).min(400.0),
        );
        let mut brightness = ndarray::Zip::from(&radiance)
            .par_map_collect(|&r| bt_table.inverse(r).unwrap_or_else(|| brightness_temperature(lo, hi, r)));
        let ir = &config.ir;
        let resolution_pixels = ir.resolution / scene.grid.pixel_spacing;
        if ir.noise || resolution_pixels > 1.0 {
            let formation = IrFormation {
                resolution_pixels,
                netd: if ir.noise { ir.netd } else { 0.0 },
            };
            let seed = config.seed ^ (0x1A1A_0000 + band as u64);
            brightness = form_ir_image(&brightness, formation, seed);
        }
        let flat = view.facet(0.0, 0.0, t_surface);
        IrImage {
            band,
            radiance,
            brightness_temperature: brightness,
            info: IrInfo {
                band: band.name(),
                wavelength_range_um: band.range(),
                incidence_deg: config.platform.incidence,
                look_direction_deg: config.platform.look_direction,
                sun_elevation_deg: config.ir.sun_elevation,
                sun_azimuth_deg: config.ir.sun_azimuth,
                refractive_index: (view.index.re, -view.index.im),
                sea_surface_temperature_k: t_surface,
                flat_sea: flat,
                netd_k: ir.noise.then_some(ir.netd),
            },
        }
    }
}
