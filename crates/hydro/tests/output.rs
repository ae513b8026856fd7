//! The hydro stage's files.

use wakelab_core::{WakelabConfig, WakelabError};
use wakelab_hydro::output::run_hydro_stage;

fn tiny() -> WakelabConfig {
    WakelabConfig::from_toml_str(
        "[grid]\ncore_width = 200.0\ndepth = 30.0\ncore_cells = 60\ndepth_cells = 15\nbeach_width = 60.0\nbeach_cells = 6\n\
         [time]\nduration = 120.0\nsurface_interval = 20.0\noutput_interval = 60.0\n\
         [scene]\nsize = 32\nalong_track = 500.0\n[sea]\nwindow = 16\n",
        "test",
    )
    .unwrap()
}

#[test]
fn a_cancelled_run_leaves_no_half_written_file() {
    let dir = tempfile::tempdir().unwrap();
    let err = run_hydro_stage(&tiny(), dir.path(), &mut |_, steps| {
        if steps >= 3 {
            Err(WakelabError::BlowUp {
                step: steps,
                time: 0.0,
                detail: "cancelled by the test".into(),
            })
        } else {
            Ok(())
        }
    })
    .unwrap_err();
    assert!(err.to_string().contains("cancelled"));
    let left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".nc") || n.ends_with(".tmp") || n.ends_with(".json"))
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}

#[test]
fn same_configuration_gives_the_same_bytes() {
    let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let mut quiet = |_: f64, _: usize| Ok(());
    run_hydro_stage(&tiny(), a.path(), &mut quiet).unwrap();
    run_hydro_stage(&tiny(), b.path(), &mut quiet).unwrap();
    for f in ["wake_sections.nc", "wake_surface.nc", "surface_map.nc", "surface_U.png"] {
        let (x, y) = (
            std::fs::read(a.path().join(f)).unwrap(),
            std::fs::read(b.path().join(f)).unwrap(),
        );
        assert!(x == y, "{f} differs between identical runs");
    }
}
