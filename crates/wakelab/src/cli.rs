//! Command-line arguments.

use crate::Result;
use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;
use wakelab_core::config::{Preset, WakelabConfig};
use wakelab_learn::train::Recipe;
use wakelab_schema::recipe;
use wakelab_study::learning::LearnRequest;

/// wakelab: simulate a ship's persistent wake from first principles, render what SAR and
/// infrared sensors would see, and train and fuse the detectors that find it.
///
/// Start with `wakelab run`: the whole study on the embedded default (wakes, a labelled SAR and
/// IR dataset, the spec's classifiers trained and evaluated, fusion, robustness) with a report
/// in runs/default/report/report.html. `wakelab scene` runs the physics of one configuration;
/// `wakelab config show` prints every setting: copy it to a file, change what you need and pass
/// it back with --config.
#[derive(Parser, Debug)]
#[command(name = "wakelab", version, about, long_about, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
    /// No progress bars (every command; -q).
    #[arg(long, short, global = true)]
    pub quiet: bool,
}

#[derive(Args, Debug, Clone)]
pub struct ConfigArgs {
    /// TOML configuration file; values it leaves out keep their embedded defaults.
    #[arg(long, short, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Grid and time preset: `quick` (coarse, seconds) or `paper` (the spec's grid, minutes).
    /// Overrides the file's `preset`.
    #[arg(long, value_name = "NAME")]
    pub preset: Option<Preset>,
}

impl ConfigArgs {
    pub fn load(&self) -> Result<WakelabConfig> {
        let file = self.config.as_deref();
        Ok(WakelabConfig::from_file_with_preset(file, self.preset)?)
    }

    /// The configuration with the command line's --wind and --incidence applied, validated.
    pub fn load_with(&self, wind: Option<f64>, incidence: Option<f64>) -> Result<WakelabConfig> {
        Ok(self.load()?.with_wind_and_incidence(wind, incidence)?)
    }
}

#[derive(Args, Debug, Clone)]
pub struct RunArgs {
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Run directory (default: the configuration's output.dir).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

#[derive(Args, Debug, Clone)]
pub struct StudyArgs {
    /// Study: `default` (embedded, about 11 minutes on a 2-core machine), `paper` (the spec's scale and
    /// recipe), `transfer` (detectors for real C-band images, RUN/detectors/) or a study TOML file.
    #[arg(long, value_name = "NAME|FILE")]
    pub study: Option<String>,
    /// `quick` (the default study) or `paper` (the paper study); --study wins when both are given.
    #[arg(long, value_name = "NAME")]
    pub preset: Option<Preset>,
    /// Run directory (default: runs/<study name>).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Backend for training: `auto` (the GPU backend of a build with `--features cuda` or `--features wgpu`, else the CPU), cpu, wgpu or cuda.
    #[arg(long, default_value = "auto")]
    pub device: String,
    /// Print each stage's work and its time on this CPU (from steps measured for about a minute) and on a GPU (timed on the `--device` GPU, else an H100's measured rates), and the peak memory; write nothing.
    #[arg(long, conflicts_with_all = ["emit_slurm", "stage"])]
    pub dry_run: bool,
    /// Write a Slurm script, DIR/wakelab_run.slurm, running the study as jobs chained by `afterok` (dataset shards; a job per learning input, one for held-out; fusion and the report).
    #[arg(long, conflicts_with_all = ["stage", "input"])]
    pub emit_slurm: bool,
    /// Array tasks of the Slurm script's dataset step (with --emit-slurm).
    #[arg(long, value_name = "N", requires = "emit_slurm")]
    pub tasks: Option<usize>,
    /// Cores per Slurm job (with --emit-slurm).
    #[arg(long, value_name = "N", requires = "emit_slurm")]
    pub cpus: Option<usize>,
    /// Run one learning stage only, on the run directory's finished dataset (what the Slurm jobs run): `learning` (one input, --input) or `held-out`; `wakelab run` reuses it.
    #[arg(long, value_name = "learning|held-out")]
    pub stage: Option<StageName>,
    /// The input of `--stage learning`: a band (S, C, X, MWIR, LWIR) or bands as channels (S+X).
    #[arg(long, value_name = "NAME")]
    pub input: Option<String>,
    /// Score the transfer study's detectors, and detect's classic ship and wake searches, on real images: DIR holds each with NAME.geojson of its wakes.
    #[arg(long, value_name = "DIR")]
    pub real: Option<PathBuf>,
    /// The transfer study also draws its wakes onto real SAR images without wakes (DIR, each with NAME.geojson).
    #[arg(long, value_name = "DIR")]
    pub sea_images: Option<PathBuf>,
    /// The transfer study also trains on real SAR images with their wakes drawn (DIR, each with NAME.geojson): windows along the wakes and clear of them.
    #[arg(long, value_name = "DIR")]
    pub wake_images: Option<PathBuf>,
}

/// A learning stage that `wakelab run --stage` runs on its own.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum StageName {
    Learning,
    HeldOut,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// The whole study (the main job): simulate the study's wakes, render its SAR and IR dataset,
    /// train and evaluate every architecture on every band with the spec's repetitions, fuse,
    /// stress-test, score the classic ship and wake detectors, and write a report
    /// (runs/<study>/report/report.html). Reuses every finished step whose inputs have not changed.
    #[command(after_help = include_str!("../help/run.txt"))]
    Run(StudyArgs),
    /// Run the pipeline on one configuration: wake, sea surface of the scene, SAR and IR images.
    #[command(after_help = include_str!("../help/scene.txt"))]
    Scene(RunArgs),
    /// Simulate the ship's wake only (stage 1, spec 2.1) and write its files.
    #[command(after_help = include_str!("../help/wake.txt"))]
    Wake(RunArgs),
    /// The initial data plane of the ship (spec Eqs. (2.26)-(2.62)): its derived scalars.
    #[command(after_help = include_str!("../help/idp.txt"))]
    Idp(IdpArgs),
    /// The background sea of a wind (and the configured swell): Hs, peak frequency, mean-square
    /// slopes and the spectral density at the S, C and X Bragg wavenumbers.
    #[command(after_help = include_str!("../help/spectrum.txt"))]
    Spectrum(SpectrumArgs),
    /// Infrared optics of sea water: n, kappa, Fresnel reflectances and emissivity at a
    /// wavelength, and the IR radiance of a flat sea in both bands for the configured geometry.
    #[command(after_help = include_str!("../help/optics.txt"))]
    Optics(OpticsArgs),
    /// Render a parametric study into a labelled dataset (stage 4): wake and no-wake scenes in
    /// every band, wake masks, visibility, manifest (CSV, JSON) and train/test splits.
    #[command(after_help = include_str!("../help/dataset.txt"))]
    Dataset(DatasetArgs),
    /// Train one detector (spec 4.1) on a dataset's training split, save it (safetensors, with a
    /// PyTorch-layout export) and test it on the test split.
    #[command(after_help = include_str!("../help/train.txt"))]
    Train(TrainArgs),
    /// Algorithm 2 on a dataset: repeated Monte Carlo train/test splits, every output kept, MCC,
    /// accuracy, F1 and ROC AUC per band and architecture (Tables 4.4-4.6).
    #[command(after_help = include_str!("../help/eval.txt"))]
    Eval(EvalArgs),
    /// Run a saved detector over an image of any size (a Sentinel-1, TerraSAR-X or COSMO-SkyMed
    /// product, a GeoTIFF / COG, npy or PNG) and find its ships and their wakes (course, speed).
    #[command(after_help = include_str!("../help/detect.txt"))]
    Detect(DetectArgs),
    /// Calibrate a SAR product to sigma0 (SNAP's "Calibration"): the masked sigma0 that detect
    /// scans, as a Cloud-Optimised GeoTIFF on the product's ground.
    #[command(after_help = include_str!("../help/calibrate.txt"))]
    Calibrate(CalibrateArgs),
    /// SAR tools.
    Sar {
        #[command(subcommand)]
        action: SarAction,
    },
    /// Inspect the configuration.
    Config {
        #[command(subcommand)]
        action: ConfigAction,
    },
}

#[derive(Subcommand, Debug)]
pub enum SarAction {
    /// sigma0 of the undisturbed sea for a wind, band, polarisation and incidence (spec Eqs.
    /// 3.1-3.2), to compare against the geophysical model functions you know.
    #[command(after_help = include_str!("../help/sigma0.txt"))]
    Sigma0(Sigma0Args),
}

#[derive(Subcommand, Debug)]
pub enum ConfigAction {
    /// Print the effective configuration as TOML (a valid --config file).
    #[command(after_help = include_str!("../help/config.txt"))]
    Show {
        #[command(flatten)]
        config: ConfigArgs,
    },
}

#[derive(Args, Debug)]
pub struct IdpArgs {
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Print the scalars as JSON.
    #[arg(long)]
    pub json: bool,
    /// Also write the IDP fields on the grid (idp.nc and pictures) into DIR.
    #[arg(long, value_name = "DIR")]
    pub write: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct SpectrumArgs {
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Wind speed at 10 m (m/s); default: environment.wind.speed.
    #[arg(long, value_name = "M/S", allow_negative_numbers = true)]
    pub wind: Option<f64>,
    /// Radar incidence angle (degrees); default: platform.incidence.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub incidence: Option<f64>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Args, Debug)]
pub struct OpticsArgs {
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Wavelength (micrometres).
    #[arg(long, value_name = "UM", default_value_t = 11.0)]
    pub wavelength: f64,
    /// Practical salinity (PSU); default: the surface salinity.
    #[arg(long, allow_negative_numbers = true)]
    pub salinity: Option<f64>,
    /// Temperature (deg C); default: the surface temperature.
    #[arg(long, allow_negative_numbers = true)]
    pub temperature: Option<f64>,
    /// Incidence angle (degrees); default: platform.incidence.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub incidence: Option<f64>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Args, Debug)]
pub struct DatasetArgs {
    /// Study file (TOML), or `default` / `paper` for the embedded studies.
    #[arg(long, value_name = "FILE", default_value = "default")]
    pub study: String,
    /// Dataset directory.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Render only pairs with index % N == K, given as K/N (one Slurm array task).
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Only gather finished scenes into the manifest and splits.
    #[arg(long)]
    pub merge: bool,
    /// Write a Slurm job-array script into DIR instead of rendering.
    #[arg(long)]
    pub emit_slurm: bool,
    /// Array tasks of the Slurm script.
    #[arg(long, default_value_t = 16)]
    pub tasks: usize,
}

#[derive(clap::Args, Debug, Clone)]
pub struct LearnArgs {
    /// Dataset directory (written by `wakelab dataset`).
    pub dataset: PathBuf,
    /// Inputs, comma-separated; `S+X` is one input of two bands as channels (feature-level
    /// fusion). Default: every band of the dataset, one at a time.
    #[arg(long, value_name = "LIST")]
    pub bands: Option<String>,
    /// Classifier epochs (spec: 60).
    #[arg(long, default_value_t = recipe::CLASSIFIER_EPOCHS)]
    pub epochs: usize,
    /// U-Net epochs (spec: 60).
    #[arg(long, default_value_t = recipe::UNET_EPOCHS)]
    pub unet_epochs: usize,
    /// U-Net batch size (spec: 4).
    #[arg(long, default_value_t = recipe::UNET_BATCH_SIZE)]
    pub unet_batch_size: usize,
    /// First-level channels of the U-Net (Table 4.2: 64; narrower trains faster).
    #[arg(long, default_value_t = recipe::UNET_WIDTH)]
    pub unet_width: usize,
    /// Classifier batch size.
    #[arg(long, default_value_t = recipe::CLASSIFIER_BATCH_SIZE)]
    pub batch_size: usize,
    /// Classifier learning rate (spec: 1e-3, SGD).
    #[arg(long, default_value_t = recipe::CLASSIFIER_LEARNING_RATE, allow_negative_numbers = true)]
    pub learning_rate: f64,
    /// Classifier optimiser: sgd (spec 4.1) or adam (the spec's U-Net optimiser; far fewer steps).
    #[arg(long, default_value = "sgd", value_name = "sgd|adam")]
    pub optimiser: wakelab_schema::recipe::Optimiser,
    /// Classifier L2 weight decay (spec: 0.1).
    #[arg(long, default_value_t = recipe::CLASSIFIER_WEIGHT_DECAY, allow_negative_numbers = true)]
    pub weight_decay: f64,
    /// Decision threshold on the wake probability (spec 4.2: 0.5).
    #[arg(long, default_value_t = recipe::THRESHOLD, allow_negative_numbers = true)]
    pub threshold: f64,
    /// Seed of the weights, splits, batch order and augmentation.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// How training inputs vary: quarter_turns (spec 4.2) or geometric (any rotation, flips, shifts).
    #[arg(long, default_value = "quarter_turns", value_name = "quarter_turns|geometric")]
    pub augmentation: wakelab_schema::recipe::Augmentation,
    /// Backend: cpu, or wgpu / cuda in builds with those features.
    #[arg(long, default_value = "cpu")]
    pub device: String,
    /// Output directory (default: DATASET/learn).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

impl LearnArgs {
    /// What `train` and `eval` are asked to do.
    pub fn request(&self) -> LearnRequest {
        LearnRequest {
            dataset: self.dataset.clone(),
            bands: self.bands.clone(),
            classifier: Recipe {
                epochs: self.epochs,
                batch_size: self.batch_size,
                learning_rate: self.learning_rate,
                optimiser: self.optimiser,
                weight_decay: self.weight_decay,
                augmentation: self.augmentation,
                ..Recipe::classifier()
            },
            unet: Recipe {
                epochs: self.unet_epochs,
                batch_size: self.unet_batch_size,
                width: self.unet_width,
                augmentation: self.augmentation,
                ..Recipe::unet()
            },
            threshold: self.threshold,
            seed: self.seed,
            device: self.device.clone(),
            out: self.out.clone(),
        }
    }
}

#[derive(Args, Debug)]
pub struct TrainArgs {
    #[command(flatten)]
    pub learn: LearnArgs,
    /// Architecture: base, cls or unet (Table 4.1).
    #[arg(long, default_value = "base")]
    pub arch: wakelab_schema::results::Architecture,
    /// Model file (default: OUT/BANDS_ARCH.safetensors).
    #[arg(long, value_name = "FILE")]
    pub model: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct EvalArgs {
    #[command(flatten)]
    pub learn: LearnArgs,
    /// Architectures, comma-separated.
    #[arg(long, default_value = "base,cls,unet", value_delimiter = ',')]
    pub arch: Vec<wakelab_schema::results::Architecture>,
    /// Repetitions of Algorithm 2 (spec: 5).
    #[arg(long, default_value_t = wakelab_schema::recipe::REPETITIONS)]
    pub repetitions: usize,
    /// Print the metrics as JSON.
    #[arg(long)]
    pub json: bool,
    /// Take the recipe from a study's `[learning]` table (`default`, `paper`, or a study file
    /// such as a run's `study.toml`): repetitions, epochs, optimiser, learning rates, U-Net,
    /// threshold, seed, augmentation, perturbations and inputs, so that `eval` on a run's
    /// dataset reproduces the run's tables. Recipe flags cannot be combined with it.
    #[arg(
        long,
        value_name = "default|paper|FILE",
        conflicts_with_all = [
            "epochs", "unet_epochs", "unet_batch_size", "unet_width", "batch_size", "learning_rate",
            "optimiser", "weight_decay", "threshold", "seed", "augmentation", "repetitions",
        ]
    )]
    pub study: Option<String>,
}

/// How a product is read (`detect` and `calibrate`).
#[derive(Args, Debug, Clone)]
pub struct ReadArgs {
    /// Polarisation to read (default VV, else HH); `detect` seeks ships in VH / HV where present.
    #[arg(long, value_name = "VV|HH|VH|HV")]
    pub pol: Option<String>,
    /// Keep the thermal noise in a Sentinel-1 or TerraSAR-X product's sigma0 (removed by default).
    #[arg(long)]
    pub keep_noise: bool,
    /// A raster of the input's size, non-zero on pixels to ignore (land, anything).
    #[arg(long, value_name = "FILE")]
    pub exclude: Option<PathBuf>,
    /// The scale of a radar image's pixels: linear (sigma0), db, amplitude (sqrt sigma0), display
    /// (an 8-bit stretch; probabilities uncalibrated) or dn (uncalibrated amplitude digital numbers).
    /// Default: the file's band unit, else linear. Infrared images are brightness temperatures (K).
    #[arg(long, value_name = "linear|db|amplitude|display|dn")]
    pub scale: Option<wakelab_products::InputScale>,
    /// Ground pixel spacing of a bare array (m); products state their own.
    #[arg(long, value_name = "M")]
    pub pixel_spacing: Option<f64>,
}

impl ReadArgs {
    /// The products crate's options (the quantity is set by the detector's band).
    pub fn options(&self) -> wakelab_products::ReadOptions {
        wakelab_products::ReadOptions {
            scale: self.scale,
            polarisation: self.pol.clone(),
            keep_noise: self.keep_noise,
            exclude: self.exclude.clone(),
            pixel_spacing: self.pixel_spacing,
            ..Default::default()
        }
    }
}

#[derive(Args, Debug)]
pub struct DetectArgs {
    /// The image: a Sentinel-1 GRD product (.SAFE directory, its manifest.safe, or the .zip), a
    /// TerraSAR-X MGD product (its directory), a COSMO-SkyMed .h5, a GeoTIFF / COG of sigma0 or
    /// brightness temperature, an npy array or a PNG.
    pub image: PathBuf,
    /// Detector file (`train`, `eval`, `run`); default: the shipped C-band one for the image's pixel spacing.
    #[arg(long, value_name = "FILE")]
    pub model: Option<PathBuf>,
    /// Step between the detector's windows (pixels, at most the window side); default: half a window.
    #[arg(long, value_name = "PIXELS")]
    pub stride: Option<usize>,
    /// Decision threshold on a window's wake probability; default: the detector's.
    #[arg(long, value_name = "P", allow_negative_numbers = true)]
    pub threshold: Option<f64>,
    /// Output directory (its files: below); default: detect-<image name> in the current directory.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// The peak's window: `line` (of the strongest line's contrast) or `network` (the most probable).
    #[arg(long, value_name = "RULE", default_value = "line")]
    pub peak: wakelab_learn::detect::PeakRule,
    /// Also write the wake mask (PNG) here.
    #[arg(long, value_name = "FILE")]
    pub mask: Option<PathBuf>,
    #[command(flatten)]
    pub read: ReadArgs,
    /// Backend: cpu, or wgpu / cuda in builds with those features.
    #[arg(long, default_value = "cpu")]
    pub device: String,
    /// Print JSON: the verdict, the detections, ships and wakes.
    #[arg(long)]
    pub json: bool,
    /// With --json, also every window's probability (large: one entry per window).
    #[arg(long)]
    pub windows: bool,
    /// Scan even when the input's band (from its mission, metadata or name) is not the detector's.
    #[arg(long)]
    pub force: bool,
    /// Ship search (CFAR) false-alarm probability per sea pixel, in (0, 0.01]; 1e-6, 1e-9 on display images.
    #[arg(long, value_name = "P")]
    pub ship_pfa: Option<f64>,
    /// Seek ships and wakes on land too (by default land found in the image is left out).
    #[arg(long)]
    pub no_land_mask: bool,
}

#[derive(Args, Debug)]
pub struct CalibrateArgs {
    /// The product: a Sentinel-1 GRD (.SAFE directory, manifest.safe or .zip), a TerraSAR-X MGD
    /// (its directory), a COSMO-SkyMed .h5, or a GeoTIFF.
    pub product: PathBuf,
    /// The Cloud-Optimised GeoTIFF to write.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Write sigma0 in dB (default: linear).
    #[arg(long)]
    pub db: bool,
    #[command(flatten)]
    pub read: ReadArgs,
    /// Print JSON (the product's metadata and what reading did).
    #[arg(long)]
    pub json: bool,
}

#[derive(Args, Debug)]
pub struct Sigma0Args {
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Wind speed at 10 m (m/s); default: environment.wind.speed.
    #[arg(long, value_name = "M/S", allow_negative_numbers = true)]
    pub wind: Option<f64>,
    /// Band: S, C or X.
    #[arg(long, default_value = "C")]
    pub band: wakelab_core::units::RadarBand,
    /// Polarisation: vv or hh; default: sar.polarisation.
    #[arg(long)]
    pub polarisation: Option<wakelab_core::config::Polarisation>,
    /// Incidence angle (degrees); default: platform.incidence.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub incidence: Option<f64>,
    /// Look direction relative to the wind direction (degrees; 0: looking down-wind).
    #[arg(long, value_name = "DEG", default_value_t = 90.0, allow_negative_numbers = true)]
    pub look: f64,
    /// Side of the cell the sea is seen in (m): waves longer than it are resolved, shorter ones
    /// tilt the Bragg facets; default: scene.pixel_spacing (the background of an image).
    /// CMOD5.N's cell is 25000, as in the study report's figure.
    #[arg(long, value_name = "M")]
    pub cell: Option<f64>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}
