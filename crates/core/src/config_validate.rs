//! Range checks of every configuration value (`WakelabConfig::validate`): each error names the
//! field as written in TOML, its value and the allowed range.

use crate::config::{Profile, SwellDirection, WakelabConfig};
use crate::error::ConfigError;

impl WakelabConfig {
    /// Check every value against its allowed range; the error names the field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let s = &self.ship;
        positive("ship.length", s.length, 1.0, 500.0, "m")?;
        positive("ship.beam", s.beam, 0.5, 100.0, "m")?;
        positive("ship.draft", s.draft, 0.1, 40.0, "m")?;
        positive("ship.wetted_area", s.wetted_area, 1.0, 1.0e5, "m^2")?;
        positive("ship.speed", s.speed, 0.1, 30.0, "m/s")?;
        positive("ship.propeller_diameter", s.propeller_diameter, 0.1, 20.0, "m")?;
        range(
            "ship.propeller_offset",
            s.propeller_offset,
            0.0,
            s.beam,
            "m (0 to the beam)",
        )?;
        positive("ship.propeller_depth", s.propeller_depth, 0.1, 40.0, "m")?;
        range("ship.rudder_offset", s.rudder_offset, 0.0, s.beam, "m (0 to the beam)")?;
        positive("ship.rudder_depth", s.rudder_depth, 0.05, 40.0, "m")?;
        positive("ship.rudder_thickness", s.rudder_thickness, 0.01, 10.0, "m")?;
        positive("ship.rudder_chord", s.rudder_chord, 0.05, 50.0, "m")?;
        positive("ship.rudder_area", s.rudder_area, 0.01, 500.0, "m^2")?;
        range("ship.swirl_number", s.swirl_number, 0.0, 2.0, "")?;
        positive("ship.rudder_drag_coefficient", s.rudder_drag_coefficient, 1e-6, 2.0, "")?;
        range("ship.wave_drag_coefficient", s.wave_drag_coefficient, 0.0, 0.1, "")?;
        let c = &s.coefficients;
        for (name, v) in [
            ("a1", c.a1),
            ("a2", c.a2),
            ("a3", c.a3),
            ("a4", c.a4),
            ("a", c.a),
            ("a_p", c.a_p),
            ("a_s1", c.a_s1),
            ("a_s2", c.a_s2),
            ("alpha_theta", c.alpha_theta),
            ("c_delta", c.c_delta),
        ] {
            positive(&format!("ship.coefficients.{name}"), v, 1e-6, 100.0, "")?;
        }

        let e = &self.environment;
        range("environment.latitude", e.latitude, -90.0, 90.0, "degrees")?;
        range("environment.longitude", e.longitude, -180.0, 360.0, "degrees")?;
        positive("environment.gravity", e.gravity, 9.7, 9.9, "m/s^2")?;
        positive(
            "environment.kinematic_viscosity",
            e.kinematic_viscosity,
            1e-7,
            1e-4,
            "m^2/s",
        )?;
        positive(
            "environment.reference_density",
            e.reference_density,
            990.0,
            1060.0,
            "kg/m^3",
        )?;
        validate_profile("environment.temperature", &e.temperature, -2.0, 40.0, self.grid.depth)?;
        validate_profile("environment.salinity", &e.salinity, 2.0, 42.0, self.grid.depth)?;
        range("environment.swell.amplitude", e.swell.amplitude, 0.0, 10.0, "m")?;
        positive("environment.swell.wavelength", e.swell.wavelength, 5.0, 1000.0, "m")?;
        if e.swell.amplitude > 0.0 {
            let steepness = e.swell.amplitude * 2.0 * std::f64::consts::PI / e.swell.wavelength;
            if steepness > 0.3 {
                return Err(ConfigError::new(
                    "environment.swell.amplitude",
                    e.swell.amplitude,
                    format!(
                        "steepness a k = {steepness:.3} must be at most 0.3 for a Stokes wave \
                         (amplitude at most {:.3} m for this wavelength)",
                        0.3 * e.swell.wavelength / (2.0 * std::f64::consts::PI)
                    ),
                ));
            }
        }
        if let SwellDirection::Degrees(d) = e.swell.direction {
            range(
                "environment.swell.direction",
                d,
                -360.0,
                360.0,
                "degrees, or calm/following/head/beam",
            )?;
        }
        range("environment.wind.speed", e.wind.speed, 0.0, 40.0, "m/s")?;
        range("environment.wind.direction", e.wind.direction, -360.0, 360.0, "degrees")?;
        range(
            "environment.wind.variability",
            e.wind.variability,
            0.0,
            0.5,
            "(relative standard deviation)",
        )?;
        positive("environment.wind.gust_length", e.wind.gust_length, 10.0, 1.0e5, "m")?;
        positive("environment.ambient_tke", e.ambient_tke, 1e-12, 1e-2, "m^2/s^2")?;
        positive(
            "environment.ambient_dissipation",
            e.ambient_dissipation,
            1e-15,
            1e-2,
            "m^2/s^3",
        )?;

        let g = &self.grid;
        positive("grid.core_width", g.core_width, 10.0, 20_000.0, "m")?;
        positive("grid.depth", g.depth, 5.0, 2000.0, "m")?;
        count("grid.core_cells", g.core_cells, 8, 20_001)?;
        count("grid.depth_cells", g.depth_cells, 4, 2001)?;
        range("grid.beach_width", g.beach_width, 0.0, 20_000.0, "m")?;
        if g.beach_width > 0.0 {
            count("grid.beach_cells", g.beach_cells, 2, 2001)?;
        } else if g.beach_cells != 0 {
            return Err(ConfigError::new(
                "grid.beach_cells",
                g.beach_cells,
                "0 when grid.beach_width is 0",
            ));
        }
        let deepest = s.propeller_depth + s.propeller_diameter;
        if g.depth < 2.0 * deepest {
            return Err(ConfigError::new(
                "grid.depth",
                g.depth,
                format!(
                    "at least {:.1} m (twice the propeller depth plus diameter)",
                    2.0 * deepest
                ),
            ));
        }
        if g.core_width < 4.0 * s.beam {
            return Err(ConfigError::new(
                "grid.core_width",
                g.core_width,
                format!("at least {:.1} m (four beams)", 4.0 * s.beam),
            ));
        }

        let t = &self.time;
        positive("time.duration", t.duration, 1.0, 86_400.0, "s")?;
        positive("time.cfl", t.cfl, 0.01, 0.9, "")?;
        positive("time.max_dt", t.max_dt, 1e-3, 600.0, "s")?;
        positive(
            "time.surface_interval",
            t.surface_interval,
            1e-2,
            t.duration,
            "s (up to time.duration)",
        )?;
        positive(
            "time.output_interval",
            t.output_interval,
            1e-2,
            t.duration,
            "s (up to time.duration)",
        )?;

        let so = &self.solver;
        range("solver.beach_damping", so.beach_damping, 0.0, 10.0, "1/s")?;
        positive("solver.max_eddy_viscosity", so.max_eddy_viscosity, 1e-4, 100.0, "m^2/s")?;

        let sea = &self.sea;
        positive("sea.inverse_wave_age", sea.inverse_wave_age, 0.84, 5.0, "")?;
        positive("sea.short_wave_exponent", sea.short_wave_exponent, 3.0, 5.0, "")?;
        positive(
            "sea.short_wave_join",
            sea.short_wave_join,
            1.5,
            1000.0,
            "multiples of k_p",
        )?;
        positive("sea.swell_width", sea.swell_width, 0.01, 0.5, "")?;
        positive("sea.swell_spread", sea.swell_spread, 1.0, 60.0, "degrees")?;
        range("sea.film_elasticity", sea.film_elasticity, 0.0, 0.08, "N/m")?;
        positive("sea.surface_tension", sea.surface_tension, 0.05, 0.08, "N/m")?;
        if !(16..=4096).contains(&sea.window) || sea.window % 2 != 0 {
            return Err(ConfigError::new(
                "sea.window",
                sea.window,
                "an even number of pixels in [16, 4096]",
            ));
        }

        let sc = &self.scene;
        positive("scene.pixel_spacing", sc.pixel_spacing, 0.1, 1000.0, "m")?;
        count("scene.size", sc.size, 16, 8192)?;
        if sea.window > sc.size {
            return Err(ConfigError::new(
                "sea.window",
                sea.window,
                format!("at most scene.size = {} pixels", sc.size),
            ));
        }
        let wake_end = self.wake_end();
        for (i, w) in sc.wake_placements().iter().enumerate() {
            // the scene's own wake is named by its fields, the others by their index
            let field = |name: &str| match i {
                0 => format!("scene.{name}"),
                _ => format!("scene.other_wakes[{}].{name}", i - 1),
            };
            range(&field("heading"), w.heading, -360.0, 360.0, "degrees")?;
            let half = 0.5 * sc.size as f64 * sc.pixel_spacing;
            // how far astern of its centre the scene reaches along the track, at its heading
            let (sin, cos) = w.heading.to_radians().sin_cos();
            let reach = half * (sin.abs() + cos.abs());
            if w.along_track < 0.0 || w.along_track + reach > wake_end {
                return Err(ConfigError::new(
                    field("along_track"),
                    w.along_track,
                    format!(
                        "the scene (reaching {reach:.0} m astern of its centre at heading {}) must end within the \
                         simulated wake, 0..{wake_end:.0} m behind the stern: centre in [0, {:.0}] m",
                        w.heading,
                        wake_end - reach
                    ),
                ));
            }
            range(&field("cross_track"), w.cross_track, -20_000.0, 20_000.0, "m")?;
        }

        let sl = &self.slicks;
        range("slicks.coverage", sl.coverage, 0.0, 0.9, "(fraction of the scene)")?;
        positive("slicks.length", sl.length, 1.0, 1.0e5, "m")?;
        range("slicks.elongation", sl.elongation, 1.0, 50.0, "(length over width)")?;
        range("slicks.elasticity", sl.elasticity, 0.0, 0.1, "N/m")?;

        let k = &self.kelvin;
        if let Some(rcs) = k.ship_rcs {
            range("kelvin.ship_rcs", rcs, 0.0, 1.0e8, "m^2")?;
        }
        range(
            "kelvin.hull_temperature_excess",
            k.hull_temperature_excess,
            -20.0,
            100.0,
            "K",
        )?;
        range("kelvin.hull_emissivity", k.hull_emissivity, 0.0, 1.0, "")?;

        let p = &self.platform;
        range("platform.incidence", p.incidence, 15.0, 70.0, "degrees")?;
        range("platform.look_direction", p.look_direction, -360.0, 360.0, "degrees")?;

        let sar = &self.sar;
        if sar.looks > 1000 {
            return Err(ConfigError::new(
                "sar.looks",
                sar.looks,
                "an integer in [0, 1000] (0: no speckle)",
            ));
        }
        if let Some(nesz) = sar.nesz {
            range("sar.nesz", nesz, -60.0, 0.0, "dB")?;
        }
        range("sar.nesz_s", sar.nesz_s, -60.0, 0.0, "dB")?;
        range("sar.nesz_c", sar.nesz_c, -60.0, 0.0, "dB")?;
        range("sar.nesz_x", sar.nesz_x, -60.0, 0.0, "dB")?;
        range(
            "sar.resolution",
            sar.resolution,
            0.0,
            1000.0,
            "m (0: the pixel spacing)",
        )?;
        range("sar.range_to_velocity", sar.range_to_velocity, 0.0, 500.0, "s")?;
        let ir = &self.ir;
        range("ir.sun_elevation", ir.sun_elevation, -90.0, 90.0, "degrees")?;
        range("ir.sun_azimuth", ir.sun_azimuth, -360.0, 360.0, "degrees")?;
        range("ir.sun_temperature", ir.sun_temperature, 3000.0, 7000.0, "K")?;
        range("ir.sun_asymmetry", ir.sun_asymmetry, 0.0, 0.999, "")?;
        range("ir.netd", ir.netd, 0.0, 10.0, "K")?;
        range("ir.resolution", ir.resolution, 0.0, 10_000.0, "m (0: the pixel)")?;
        range(
            "ir.sky_zenith_temperature",
            ir.sky_zenith_temperature,
            150.0,
            320.0,
            "K",
        )?;
        range(
            "ir.sky_horizon_temperature",
            ir.sky_horizon_temperature,
            150.0,
            320.0,
            "K",
        )?;

        let o = &self.output;
        if o.dir.trim().is_empty() {
            return Err(ConfigError::new("output.dir", "\"\"", "a non-empty path"));
        }
        positive("output.map_dx", o.map_dx, 0.1, 10_000.0, "m")?;
        Ok(())
    }
}

fn range(field: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<(), ConfigError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(ConfigError::new(
            field,
            v,
            format!("must be in [{lo}, {hi}] {unit}").trim_end().to_string(),
        ))
    }
}

fn positive(field: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<(), ConfigError> {
    range(field, v, lo, hi, unit)
}

fn count(field: &str, v: usize, lo: usize, hi: usize) -> Result<(), ConfigError> {
    if (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(ConfigError::new(
            field,
            v,
            format!("must be an integer in [{lo}, {hi}]"),
        ))
    }
}

fn validate_profile(field: &str, p: &Profile, lo: f64, hi: f64, depth: f64) -> Result<(), ConfigError> {
    range(&format!("{field}.surface"), p.surface, lo, hi, "")?;
    range(
        &format!("{field}.depth_gradient"),
        p.depth_gradient,
        -1.0,
        1.0,
        "per metre of depth",
    )?;
    range(
        &format!("{field}.mixed_layer_depth"),
        p.mixed_layer_depth,
        0.0,
        depth,
        "m (0 to grid.depth)",
    )?;
    let bottom = p.at_depth(depth);
    if !(lo..=hi).contains(&bottom) {
        return Err(ConfigError::new(
            format!("{field}.depth_gradient"),
            p.depth_gradient,
            format!("the profile reaches {bottom:.3} at the bottom ({depth} m); it must stay in [{lo}, {hi}]"),
        ));
    }
    Ok(())
}
