//! Reading a dataset rendered by the data stage.

use wakelab_dataset::study::{Band, Study};
use wakelab_learn::data::Dataset;

#[test]
fn a_rendered_dataset_reads_back_normalised_in_every_band() {
    let study = Study::from_toml_str(
        "[study]\nname = \"t\"\ncombine = \"product\"\nseeds = 1\ntest_fraction = 0.5\ngrouped_split = false\n\
         min_visibility = 0.0\nmixed_layer_depth = 20.0\nbands = [\"C\", \"LWIR\"]\n\
         [axes]\nwind_speed = [5.0, 8.0]\nimage_size = [32]\npixel_spacing = [10.0]\nalong_track = [2000.0]\n\
         [base]\npreset = \"quick\"\n[base.time]\nduration = 600.0\n",
        "test",
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    wakelab_dataset::render_dataset(&study, dir.path(), None, None, &|_| {}).unwrap();
    wakelab_dataset::write_manifest(&study, dir.path()).unwrap();
    let ds = Dataset::open(dir.path()).unwrap();
    assert_eq!(ds.records.len(), 4);
    for i in 0..ds.records.len() {
        for band in [Band::C, Band::Lwir] {
            let img = ds.image(i, band).unwrap();
            assert_eq!(img.dim(), (32, 32));
            // the detector's input: radar in dB and infrared as anomaly, both about their median
            let median = wakelab_learn::data::median(&img);
            assert!(median.abs() < 1e-5, "{band}: median {median}");
        }
    }
    let err = ds.image(0, Band::X).unwrap_err().to_string();
    assert!(err.contains("no band X"), "{err}");
}
