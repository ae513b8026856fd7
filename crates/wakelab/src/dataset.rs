//! `wakelab dataset`: a parametric study rendered into a labelled dataset.

use crate::cli::DatasetArgs;
use crate::Result;
use wakelab_study::dataset::{emit_dataset_slurm, merge_dataset, render_dataset};

pub fn run_dataset(args: &DatasetArgs) -> Result<()> {
    let study = wakelab_study::load_study(&args.study)?;
    if args.emit_slurm {
        eprintln!("{}", emit_dataset_slurm(&study, &args.study, &args.out, args.tasks)?.1);
        return Ok(());
    }
    let shard: Option<wakelab_dataset::Shard> = (args.shard.as_deref())
        .map(|text| text.parse().map_err(|e| anyhow::anyhow!("--shard {text}: {e}")))
        .transpose()?;
    if !args.merge {
        eprintln!("{}", render_dataset(&study, &args.out, shard, args.quiet)?);
    }
    if shard.is_none() || args.merge {
        eprintln!("{}", merge_dataset(&study, &args.out)?);
    }
    Ok(())
}
