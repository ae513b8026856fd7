//! Trained detectors on disk: safetensors with what the network is in its metadata (architecture,
//! bands, input size, threshold, U-Net width, input normalisation), checked before any weight is
//! read, the weights' shapes checked against that network, and an export in
//! PyTorch's layout (`*.pytorch.safetensors`: linear weights transposed, BatchNorm's
//! gamma/beta named weight/bias) for users on the PyTorch side.

use crate::models::{Architecture, UNet, WakeClassifier};
use burn::module::Module;
use burn::store::{BurnToPyTorchAdapter, ModuleSnapshot, SafetensorsStore};
use burn::tensor::Device;
use safetensors::tensor::Metadata;
use safetensors::SafeTensors;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use wakelab_core::io::write_atomically;
use wakelab_core::WakelabError;
use wakelab_schema::architecture::{ClassifierHead, InputForm};
use wakelab_schema::band::Input;

/// A trained detector: the classifier and, for the "unet" architecture, the U-Net whose mask it
/// reads.
#[derive(Module, Debug)]
pub struct Detector {
    pub classifier: WakeClassifier,
    pub segmenter: Option<UNet>,
}

/// The detector file format this wakelab writes and reads. Format 2 added the input
/// normalisation; format 1 files are refused with a message to retrain.
pub const FORMAT: &str = "wakelab-detector-2";

/// The format of a detector that reads line sums ([`InputForm::LineSums`]): format 2 with
/// `wakelab.input_form`, numbered apart so that a wakelab reading only format 2, which knows no
/// input form, refuses it instead of scoring its windows' pixels.
pub const LINE_SUMS_FORMAT: &str = "wakelab-detector-3";

/// The format of a detector whose classifier pools its last map ([`ClassifierHead::GlobalMax`]):
/// format 3 with `wakelab.head`, numbered apart so that a wakelab that knows no head refuses it.
pub const HEAD_FORMAT: &str = "wakelab-detector-4";

/// How this wakelab makes a detector's input from an image ([`crate::data::detector_input`]),
/// recorded in every detector file: a detector only scores inputs made the same way. Change it
/// whenever `detector_input` changes.
pub const INPUT_NORMALISATION: &str =
    "robust-v1: radar sigma0 in dB, infrared brightness temperature; (v - median) / (1.4826 MAD)";

/// What a saved detector is; stored as safetensors metadata under `wakelab.*` keys.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelInfo {
    pub architecture: Architecture,
    /// Bands the input channels come from, in order.
    pub bands: Input,
    /// Side of the square input images (pixels).
    pub input_size: usize,
    /// Decision threshold on the wake probability.
    pub threshold: f64,
    /// First-level channels of the "unet" detector's U-Net (Table 4.2: 64).
    #[serde(default = "default_unet_width")]
    pub unet_width: usize,
    /// Ground pixel spacing of the training images (m); None in files written before it was
    /// recorded.
    #[serde(default)]
    pub pixel_spacing: Option<f64>,
    /// Looks of the training images' speckle.
    #[serde(default)]
    pub looks: Option<f64>,
    /// The scale of the training images' radar pixels ("linear": wakelab renders linear sigma0).
    #[serde(default)]
    pub input_scale: Option<String>,
    /// How its probabilities were calibrated and its threshold set (None: raw scores and the
    /// study's threshold).
    #[serde(default)]
    pub calibration: Option<Calibration>,
    /// What the classifier reads of each window; recorded as `wakelab.input_form` when it is
    /// not the pixels (files without it read pixels, as every detector did before).
    #[serde(default)]
    pub input_form: InputForm,
    /// How the classifier decides from its last map; recorded as `wakelab.head` when it is not
    /// Table 4.1's flatten.
    #[serde(default)]
    pub head: ClassifierHead,
}

/// A detector's calibration ([`crate::calibration`]): the temperature its logit is divided by,
/// and the false-alarm rate on simulated open sea its threshold was set for.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Calibration {
    /// T of p' = sigmoid(logit(p) / T), fitted on the test chips of the detector's own training
    /// run (chips it never trained on).
    pub temperature: f64,
    /// Alarms per 1,000 km^2 the threshold allows on simulated open sea with look-alikes, and
    /// the area that set it (km^2); None: the threshold was not set for an alarm rate.
    pub false_alarms_per_1000_km2: Option<f64>,
    pub open_sea_km2: Option<f64>,
}

fn default_unet_width() -> usize {
    crate::models::UNET_WIDTH
}

impl ModelInfo {
    fn to_metadata(&self) -> BTreeMap<String, String> {
        let mut meta = BTreeMap::from([
            (
                "wakelab.format".to_string(),
                match (self.head, self.input_form) {
                    (ClassifierHead::GlobalMax, _) => HEAD_FORMAT,
                    (ClassifierHead::Flatten, InputForm::Pixels) => FORMAT,
                    (ClassifierHead::Flatten, InputForm::LineSums | InputForm::LineSumsShipsMasked) => LINE_SUMS_FORMAT,
                }
                .to_string(),
            ),
            ("wakelab.normalisation".to_string(), INPUT_NORMALISATION.to_string()),
            ("wakelab.architecture".to_string(), self.architecture.name().to_string()),
            ("wakelab.bands".to_string(), band_list(&self.bands)),
            ("wakelab.input_size".to_string(), self.input_size.to_string()),
            ("wakelab.threshold".to_string(), self.threshold.to_string()),
            ("wakelab.unet_width".to_string(), self.unet_width.to_string()),
            ("wakelab.version".to_string(), env!("CARGO_PKG_VERSION").to_string()),
        ]);
        let optional = [
            ("wakelab.pixel_spacing", self.pixel_spacing.map(|v| v.to_string())),
            ("wakelab.looks", self.looks.map(|v| v.to_string())),
            ("wakelab.input_scale", self.input_scale.clone()),
            (
                "wakelab.input_form",
                (self.input_form != InputForm::Pixels).then(|| self.input_form.name().to_string()),
            ),
            (
                "wakelab.head",
                (self.head != ClassifierHead::Flatten).then(|| self.head.name().to_string()),
            ),
            (
                "wakelab.temperature",
                self.calibration.as_ref().map(|c| c.temperature.to_string()),
            ),
            (
                "wakelab.false_alarms_per_1000_km2",
                self.calibration
                    .as_ref()
                    .and_then(|c| c.false_alarms_per_1000_km2)
                    .map(|v| v.to_string()),
            ),
            (
                "wakelab.open_sea_km2",
                self.calibration
                    .as_ref()
                    .and_then(|c| c.open_sea_km2)
                    .map(|v| v.to_string()),
            ),
        ];
        for (key, value) in optional {
            if let Some(v) = value {
                meta.insert(key.to_string(), v);
            }
        }
        meta
    }

    fn from_metadata(meta: &BTreeMap<String, String>, path: &Path) -> Result<Self, WakelabError> {
        let err = |message: String| WakelabError::Model {
            path: path.display().to_string(),
            message,
        };
        let get = |key: &str| {
            meta.get(key)
                .ok_or_else(|| err(format!("no `{key}` in the metadata: not a wakelab detector file")))
        };
        match get("wakelab.format")?.as_str() {
            FORMAT | LINE_SUMS_FORMAT | HEAD_FORMAT => {}
            "wakelab-detector-1" => {
                return Err(err(
                    "written by an earlier wakelab (format wakelab-detector-1), which does not record how its inputs were normalised; its scores on today's inputs would be wrong without warning: retrain it (wakelab train)".into(),
                ))
            }
            other => return Err(err(format!("unknown format \"{other}\" (this wakelab reads {FORMAT}, {LINE_SUMS_FORMAT} and {HEAD_FORMAT})"))),
        }
        let normalisation = get("wakelab.normalisation")?;
        if normalisation != INPUT_NORMALISATION {
            return Err(err(format!(
                "its inputs were normalised as \"{normalisation}\", this wakelab's as \"{INPUT_NORMALISATION}\": retrain it (wakelab train)"
            )));
        }
        let architecture = Architecture::parse(get("wakelab.architecture")?)
            .ok_or_else(|| err(format!("unknown architecture {}", meta["wakelab.architecture"])))?;
        Ok(Self {
            architecture,
            bands: get("wakelab.bands")?
                .replace(',', "+")
                .parse()
                .map_err(|e| err(format!("bands: {e}")))?,
            input_size: get("wakelab.input_size")?
                .parse()
                .map_err(|e| err(format!("input_size: {e}")))?,
            threshold: get("wakelab.threshold")?
                .parse()
                .map_err(|e| err(format!("threshold: {e}")))?,
            // files written before the width was configurable hold Table 4.2's U-Net
            unet_width: match meta.get("wakelab.unet_width") {
                Some(w) => w.parse().map_err(|e| err(format!("unet_width: {e}")))?,
                None => default_unet_width(),
            },
            pixel_spacing: optional_number(meta, "wakelab.pixel_spacing").map_err(err)?,
            looks: optional_number(meta, "wakelab.looks").map_err(err)?,
            input_scale: meta.get("wakelab.input_scale").cloned(),
            calibration: match optional_number(meta, "wakelab.temperature").map_err(err)? {
                Some(temperature) if temperature > 0.0 && temperature.is_finite() => Some(Calibration {
                    temperature,
                    false_alarms_per_1000_km2: optional_number(meta, "wakelab.false_alarms_per_1000_km2")
                        .map_err(err)?,
                    open_sea_km2: optional_number(meta, "wakelab.open_sea_km2").map_err(err)?,
                }),
                Some(t) => return Err(err(format!("temperature {t}: must be a positive number"))),
                None => None,
            },
            input_form: match meta.get("wakelab.input_form") {
                Some(f) => f.parse().map_err(|e| err(format!("input_form: {e}")))?,
                None => InputForm::Pixels,
            },
            head: match meta.get("wakelab.head") {
                Some(h) => h.parse().map_err(|e| err(format!("head: {e}")))?,
                None => ClassifierHead::Flatten,
            },
        })
    }

    /// What a scan's user should know of the detector's calibration: "probabilities calibrated
    /// (temperature 1.05); threshold 0.9714 set for 1 alarm per 1,000 km^2 on 1049 km^2 of
    /// simulated open sea". None for a detector of raw scores.
    pub fn calibration_note(&self) -> Option<String> {
        let c = self.calibration.as_ref()?;
        let mut note = format!("probabilities calibrated (temperature {:.2})", c.temperature);
        if let (Some(rate), Some(km2)) = (c.false_alarms_per_1000_km2, c.open_sea_km2) {
            note += &format!(
                "; threshold {:.4} set for {rate} alarm(s) per 1,000 km^2 on {km2:.0} km^2 of simulated open sea",
                self.threshold
            );
        }
        Some(note)
    }

    /// What a scan's user should know of the detector's input: None for one reading pixels.
    pub fn input_note(&self) -> Option<String> {
        let pooled = match self.head {
            ClassifierHead::Flatten => "",
            ClassifierHead::GlobalMax => "; its classifier pools its last map to each channel's largest response",
        };
        (self.input_form != InputForm::Pixels || !pooled.is_empty()).then(|| match self.input_form {
            InputForm::LineSums => {
                format!("the detector reads each window's line sums (its Radon transform), not its pixels{pooled}")
            }
            InputForm::LineSumsShipsMasked => format!(
                "the detector reads each window's line sums (its Radon transform) with its ships' returns masked out, not its pixels{pooled}"
            ),
            InputForm::Pixels => format!("the detector reads each window's pixels{pooled}"),
        })
    }

    /// A window's wake probability as the detector reports it: its network's output scaled by
    /// its calibration's temperature, if it has one.
    pub fn probability(&self, network_output: f64) -> f64 {
        match &self.calibration {
            Some(c) => crate::calibration::scaled(network_output, c.temperature),
            None => network_output,
        }
    }

    /// Image channels the detector reads (one per band).
    pub fn image_channels(&self) -> usize {
        self.bands.bands().len()
    }

    /// The band of a single-band detector (what `detect` scans); refused, naming `--model`,
    /// for a detector of several bands.
    pub fn single_band(&self) -> Result<wakelab_schema::band::Band, wakelab_core::ConfigError> {
        self.bands.as_single().ok_or_else(|| {
            wakelab_core::ConfigError::new(
                "--model",
                format!("a detector of {} bands ({})", self.image_channels(), self.bands),
                "a single-band detector",
            )
        })
    }
}

/// A number under `key` when the metadata has one (files written before it was recorded
/// have none).
fn optional_number(meta: &BTreeMap<String, String>, key: &str) -> Result<Option<f64>, String> {
    meta.get(key)
        .map(|v| v.parse().map_err(|e| format!("{key}: \"{v}\": {e}")))
        .transpose()
}

/// The metadata's band list: names joined by commas ("S,X").
fn band_list(input: &Input) -> String {
    input.bands().iter().map(|b| b.name()).collect::<Vec<_>>().join(",")
}

fn store_error(path: &Path, e: impl std::fmt::Display) -> WakelabError {
    WakelabError::Model {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// The `__metadata__` of a safetensors file, reading only its header (an 8-byte little-endian
/// length and that much JSON), which the `safetensors` crate parses.
pub fn read_metadata(path: &Path) -> Result<BTreeMap<String, String>, WakelabError> {
    use std::io::Read;
    let io = |e| WakelabError::io(path, e);
    let mut file = std::fs::File::open(path).map_err(io)?;
    let mut length = [0u8; 8];
    let not = || store_error(path, "not a safetensors file");
    file.read_exact(&mut length).map_err(|_| not())?;
    let length = u64::from_le_bytes(length);
    if length > file.metadata().map_err(io)?.len() {
        return Err(not());
    }
    let mut header = Vec::with_capacity(length as usize);
    file.take(length).read_to_end(&mut header).map_err(io)?;
    let parsed: Metadata = serde_json::from_slice(&header).map_err(|_| not())?;
    Ok(metadata_in(&parsed))
}

/// The JSON header of a safetensors file (an 8-byte little-endian length, then a JSON object)
/// and the offset where its data begin: what [`canonical_safetensors`] rewrites.
fn header_of(bytes: &[u8]) -> Result<(serde_json::Value, usize), String> {
    let not = || "not a safetensors file".to_string();
    let len = u64::from_le_bytes(bytes.get(..8).ok_or_else(not)?.try_into().map_err(|_| not())?) as usize;
    let end = 8usize.checked_add(len).filter(|&e| e <= bytes.len()).ok_or_else(not)?;
    let header: serde_json::Value = serde_json::from_slice(&bytes[8..end]).map_err(|_| not())?;
    if !header.is_object() {
        return Err(not());
    }
    Ok((header, end))
}

/// The header's `__metadata__` in key order.
fn metadata_in(header: &Metadata) -> BTreeMap<String, String> {
    header
        .metadata()
        .iter()
        .flatten()
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect()
}

/// The metadata key that marks the PyTorch-layout export, which `detect` does not read.
const LAYOUT_KEY: &str = "wakelab.layout";

/// Whether a file holds the PyTorch-layout export: marked so in its metadata, or, for files
/// written before the mark, holding a normalisation layer's PyTorch names (`weight`, `bias`)
/// where burn's are `gamma`, `beta`.
fn is_pytorch_export(
    meta: &BTreeMap<String, String>,
    tensors: &BTreeMap<String, Vec<usize>>,
    detector: &Detector,
) -> bool {
    meta.get(LAYOUT_KEY).is_some_and(|l| l == "pytorch")
        || detector.collect(None, None, false).iter().any(|t| {
            t.name
                .strip_suffix(".gamma")
                .is_some_and(|layer| !tensors.contains_key(&t.name) && tensors.contains_key(&format!("{layer}.weight")))
        })
}

/// The file's tensors against the network its metadata describes: a missing, extra or
/// differently shaped tensor means the metadata and the weights disagree (an edited or damaged
/// file), said in words rather than as burn's import report.
fn check_weight_shapes(
    detector: &Detector,
    stored: &BTreeMap<String, Vec<usize>>,
    info: &ModelInfo,
) -> Result<(), String> {
    let what = format!(
        "its metadata describes \"{}\" on {} at {} x {} pixels, but its weights do not fit that network",
        info.architecture,
        band_list(&info.bands),
        info.input_size,
        info.input_size
    );
    let expected = detector.collect(None, None, false);
    for t in &expected {
        let want: Vec<usize> = t.shape.iter().copied().collect();
        match stored.get(&t.name) {
            None => {
                return Err(format!(
                    "{what}: tensor `{}` is missing (an edited or damaged file?)",
                    t.name
                ))
            }
            Some(have) if *have != want => {
                return Err(format!(
                    "{what}: `{}` is {have:?} in the file, {want:?} in that network (an edited or damaged file?)",
                    t.name
                ))
            }
            Some(_) => {}
        }
    }
    if let Some(extra) = stored.keys().find(|k| !expected.iter().any(|t| &t.name == *k)) {
        return Err(format!("{what}: the file holds `{extra}`, which that network has not"));
    }
    Ok(())
}

/// JSON text of `v` with every object's keys sorted.
fn canonical_json(v: &serde_json::Value) -> String {
    match v {
        serde_json::Value::Object(map) => {
            let mut keys: Vec<&String> = map.keys().collect();
            keys.sort();
            let items: Vec<String> = keys
                .into_iter()
                .map(|k| format!("{}:{}", serde_json::Value::String(k.clone()), canonical_json(&map[k])))
                .collect();
            format!("{{{}}}", items.join(","))
        }
        serde_json::Value::Array(items) => {
            format!("[{}]", items.iter().map(canonical_json).collect::<Vec<_>>().join(","))
        }
        other => other.to_string(),
    }
}

/// The same safetensors file with its header's keys sorted: the writer keeps metadata in a hash
/// map, whose order changes from run to run, and the same weights must give the same bytes.
/// Data offsets count from the end of the header, so a rewritten header moves nothing.
fn canonical_safetensors(bytes: Vec<u8>) -> Result<Vec<u8>, String> {
    let (header, end) = header_of(&bytes)?;
    let mut text = canonical_json(&header).into_bytes();
    // the format pads the header with spaces to a multiple of 8 bytes
    while text.len() % 8 != 0 {
        text.push(b' ');
    }
    let mut out = Vec::with_capacity(8 + text.len() + bytes.len() - end);
    out.extend_from_slice(&(text.len() as u64).to_le_bytes());
    out.extend_from_slice(&text);
    out.extend_from_slice(&bytes[end..]);
    Ok(out)
}

fn with_metadata(mut store: SafetensorsStore, info: &ModelInfo, layout: &str) -> SafetensorsStore {
    for (k, v) in info.to_metadata() {
        store = store.metadata(k, v);
    }
    store.metadata(LAYOUT_KEY, layout)
}

/// Save `detector` to `path` (written to a temporary file, then renamed), and its PyTorch-layout
/// export beside it. Returns both paths.
pub fn save_detector(
    detector: &Detector,
    info: &ModelInfo,
    path: &Path,
) -> Result<(std::path::PathBuf, std::path::PathBuf), WakelabError> {
    let mut store = with_metadata(SafetensorsStore::from_bytes(None), info, "burn");
    detector.save_into(&mut store).map_err(|e| store_error(path, e))?;
    let bytes = store.get_bytes().map_err(|e| store_error(path, e))?;
    let main = write_atomically(path, &canonical_safetensors(bytes).map_err(|e| store_error(path, e))?)?;
    let export = path.with_extension("pytorch.safetensors");
    let mut store =
        with_metadata(SafetensorsStore::from_bytes(None), info, "pytorch").with_to_adapter(BurnToPyTorchAdapter);
    detector.save_into(&mut store).map_err(|e| store_error(&export, e))?;
    let bytes = store.get_bytes().map_err(|e| store_error(&export, e))?;
    let export = write_atomically(
        &export,
        &canonical_safetensors(bytes).map_err(|e| store_error(&export, e))?,
    )?;
    Ok((main, export))
}

/// Load a detector. `expect` (architecture, input size), when given, must match the file's
/// metadata: a file of another architecture or input size is refused with an error saying both.
pub fn load_detector(
    path: &Path,
    expect: Option<(Architecture, usize)>,
    device: &Device,
) -> Result<(Detector, ModelInfo), WakelabError> {
    let bytes = std::fs::read(path).map_err(|e| WakelabError::io(path, e))?;
    load_detector_bytes(bytes, path, expect, device)
}

/// What a detector file's metadata says of it (architecture, band, spacing, threshold), without
/// its weights; `path` names it in errors.
pub fn detector_info(bytes: &[u8], path: &Path) -> Result<ModelInfo, WakelabError> {
    let (_, header) =
        SafeTensors::read_metadata(bytes).map_err(|e| store_error(path, format!("not a safetensors file ({e})")))?;
    ModelInfo::from_metadata(&metadata_in(&header), path)
}

/// [`load_detector`] from a detector file's bytes (a shipped detector is held in the binary);
/// `path` names it in errors.
pub fn load_detector_bytes(
    bytes: Vec<u8>,
    path: &Path,
    expect: Option<(Architecture, usize)>,
    device: &Device,
) -> Result<(Detector, ModelInfo), WakelabError> {
    let (_, header) =
        SafeTensors::read_metadata(&bytes).map_err(|e| store_error(path, format!("not a safetensors file ({e})")))?;
    let meta = metadata_in(&header);
    let stored: BTreeMap<String, Vec<usize>> = header
        .tensors()
        .into_iter()
        .map(|(name, t)| (name, t.shape.clone()))
        .collect();
    let info = ModelInfo::from_metadata(&meta, path)?;
    if let Some((architecture, size)) = expect {
        if info.architecture != architecture || info.input_size != size {
            return Err(store_error(
                path,
                format!(
                    "holds a \"{}\" model for {} x {} inputs; expected \"{}\" for {} x {}",
                    info.architecture, info.input_size, info.input_size, architecture, size, size
                ),
            ));
        }
    }
    let channels = info.architecture.classifier_channels(info.image_channels());
    let mut detector = Detector {
        classifier: WakeClassifier::with_head(channels, info.input_size, info.head, device),
        segmenter: (info.architecture == Architecture::Unet)
            .then(|| UNet::with_width(info.image_channels(), info.unet_width, device)),
    };
    if is_pytorch_export(&meta, &stored, &detector) {
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().replace(".pytorch.safetensors", ".safetensors"));
        return Err(store_error(
            path,
            format!(
                "this is the PyTorch-layout export of a detector, for loading into PyTorch; wakelab reads the \
                 detector itself ({} beside it)",
                name.unwrap_or_else(|| "the .safetensors".into())
            ),
        ));
    }
    check_weight_shapes(&detector, &stored, &info).map_err(|m| store_error(path, m))?;
    let mut store = SafetensorsStore::from_bytes(Some(bytes));
    detector.load_from(&mut store).map_err(|e| store_error(path, e))?;
    Ok((detector, info))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(calibration: Option<Calibration>) -> ModelInfo {
        ModelInfo {
            architecture: Architecture::Base,
            bands: "C".parse().unwrap(),
            input_size: 32,
            threshold: 0.93,
            unet_width: 16,
            pixel_spacing: Some(10.0),
            looks: Some(4.0),
            input_scale: Some("linear".into()),
            calibration,
            input_form: InputForm::Pixels,
            head: ClassifierHead::Flatten,
        }
    }

    /// A pooled head is written with its key and its own format, and reads back.
    #[test]
    fn the_head_reads_back_from_the_metadata() {
        let path = Path::new("m.safetensors");
        let pooled = ModelInfo {
            input_form: InputForm::LineSums,
            head: ClassifierHead::GlobalMax,
            ..info(None)
        };
        let meta = pooled.to_metadata();
        assert_eq!(meta["wakelab.head"], "global_max");
        assert_eq!(meta["wakelab.format"], HEAD_FORMAT);
        assert_eq!(ModelInfo::from_metadata(&meta, path).unwrap(), pooled);
        assert!(!info(None).to_metadata().contains_key("wakelab.head"));
        let mut wrong = meta;
        wrong.insert("wakelab.head".into(), "mean".into());
        let message = ModelInfo::from_metadata(&wrong, path).unwrap_err().to_string();
        assert!(
            message.contains("head") && message.contains("flatten, global_max"),
            "{message}"
        );
    }

    /// A detector reading line sums says so in its file; one reading pixels writes no key, so
    /// its bytes are those of a file written before the key existed, and reads back as pixels.
    #[test]
    fn the_input_form_reads_back_from_the_metadata() {
        let path = Path::new("m.safetensors");
        for (form, said) in [
            (InputForm::LineSums, "line sums"),
            (InputForm::LineSumsShipsMasked, "ships' returns masked out"),
        ] {
            let lines = ModelInfo {
                input_form: form,
                ..info(None)
            };
            let meta = lines.to_metadata();
            assert_eq!(meta["wakelab.input_form"], form.name());
            assert_eq!(meta["wakelab.format"], LINE_SUMS_FORMAT);
            assert_eq!(ModelInfo::from_metadata(&meta, path).unwrap(), lines);
            assert!(lines.input_note().is_some_and(|n| n.contains(said)));
        }
        let meta = ModelInfo {
            input_form: InputForm::LineSums,
            ..info(None)
        }
        .to_metadata();
        let pixels = info(None).to_metadata();
        assert!(!pixels.contains_key("wakelab.input_form"));
        assert_eq!(pixels["wakelab.format"], FORMAT);
        assert!(info(None).input_note().is_none());
        assert_eq!(
            ModelInfo::from_metadata(&pixels, path).unwrap().input_form,
            InputForm::Pixels
        );
        let mut wrong = meta;
        wrong.insert("wakelab.input_form".into(), "radon".into());
        let message = ModelInfo::from_metadata(&wrong, path).unwrap_err().to_string();
        assert!(
            message.contains("input_form") && message.contains("pixels, line_sums, line_sums_ships_masked"),
            "{message}"
        );
    }

    /// A calibration survives the file's metadata, and a file without one reads as raw scores.
    #[test]
    fn the_calibration_reads_back_from_the_metadata() {
        let path = Path::new("m.safetensors");
        let calibrated = info(Some(Calibration {
            temperature: 3.25,
            false_alarms_per_1000_km2: Some(1.0),
            open_sea_km2: Some(1048.576),
        }));
        let back = ModelInfo::from_metadata(&calibrated.to_metadata(), path).unwrap();
        assert_eq!(back, calibrated);
        assert!((back.probability(0.5) - 0.5).abs() < 1e-12);
        assert_eq!(
            back.calibration_note().unwrap(),
            "probabilities calibrated (temperature 3.25); threshold 0.9300 set for 1 alarm(s) per 1,000 km^2 on \
             1049 km^2 of simulated open sea"
        );
        let raw = info(None);
        assert_eq!(ModelInfo::from_metadata(&raw.to_metadata(), path).unwrap(), raw);
        assert_eq!(raw.probability(0.8), 0.8);
        assert_eq!(raw.calibration_note(), None);
        let mut meta = calibrated.to_metadata();
        meta.insert("wakelab.temperature".into(), "-1".into());
        let e = ModelInfo::from_metadata(&meta, path).unwrap_err().to_string();
        assert!(e.contains("temperature -1"), "{e}");
    }
}
