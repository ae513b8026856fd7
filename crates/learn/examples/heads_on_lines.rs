//! The classifier's two heads on the synthetic task (a line of one noise deviation, about a
//! pixel wide, on 32-pixel windows of Gaussian noise), reading pixels or line sums: the AUC and
//! MCC on 400 unseen windows after 20 epochs of Adam on 256, 512 and 1,024 windows. The figures
//! of docs/results.md ("A pooled head over the line sums"):
//!
//!     cargo run --release -p wakelab-learn --example heads_on_lines

use burn::tensor::Device;
use wakelab_learn::metrics::{roc_auc, Confusion};
use wakelab_learn::models::ClassifierHead;
use wakelab_learn::synthetic::{examples, line_versus_noise};
use wakelab_learn::train::{classify, train_classifier, Recipe};
use wakelab_schema::architecture::InputForm;
use wakelab_schema::recipe::{Augmentation, Optimiser};

fn main() {
    let device = Device::flex();
    let test = line_versus_noise(400, 32, 1.0, 99);
    let labels: Vec<u8> = test.iter().map(|s| s.label).collect();
    let test = examples(&test);
    println!("windows  input      head        AUC    MCC");
    for n in [256, 512, 1024] {
        let train = examples(&line_versus_noise(n, 32, 1.0, 7));
        for input in InputForm::ALL {
            for head in ClassifierHead::ALL {
                let recipe = Recipe {
                    epochs: 20,
                    batch_size: 16,
                    learning_rate: 1e-3,
                    optimiser: Optimiser::Adam,
                    weight_decay: 1e-4,
                    augmentation: Augmentation::Geometric,
                    input,
                    head,
                    ..Recipe::classifier()
                };
                let model = train_classifier(&train, &recipe, 3, &device, &mut |_| {}).expect("training");
                let p = classify(&model, &test, input, 64, &device);
                let mcc = Confusion::from_outputs(&p, &labels, 0.5).mcc();
                let auc = roc_auc(&p, &labels).expect("both classes");
                println!("{n:7}  {input:9}  {head:10}  {auc:.3}  {mcc:.3}");
            }
        }
    }
}
