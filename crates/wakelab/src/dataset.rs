//! `wakelab dataset`: a parametric study rendered into a labelled dataset.

use crate::cli::DatasetArgs;
use crate::Result;

pub fn run_dataset(args: &DatasetArgs, quiet: bool) -> Result<()> {
    let (shard, slurm) = (args.shard.as_deref(), args.emit_slurm.then_some(args.tasks));
    let said = wakelab_study::dataset::dataset_command(&args.study, &args.out, shard, args.merge, slurm, quiet)?;
    said.iter().for_each(|line| eprintln!("{line}"));
    Ok(())
}
