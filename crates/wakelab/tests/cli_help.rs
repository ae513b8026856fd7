//! Every subcommand's help ends with examples, and every example is a command line the binary
//! parses: run with `--help` appended, an unknown flag or a bad value fails before help prints.

mod common;

use common::*;

#[test]
fn every_subcommand_shows_examples_that_parse() {
    let subcommands: [&[&str]; 13] = [
        &["run"],
        &["scene"],
        &["wake"],
        &["idp"],
        &["spectrum"],
        &["optics"],
        &["dataset"],
        &["train"],
        &["eval"],
        &["detect"],
        &["calibrate"],
        &["sar", "sigma0"],
        &["config", "show"],
    ];
    for sub in subcommands {
        let mut args = sub.to_vec();
        args.push("--help");
        let o = wakelab(&args);
        assert!(o.status.success(), "{sub:?}: {}", stderr(&o));
        let help = stdout(&o);
        let examples: Vec<&str> = help
            .split("Examples:")
            .nth(1)
            .unwrap_or_else(|| panic!("{sub:?} --help has no examples"))
            .lines()
            .map(str::trim)
            .filter(|l| l.starts_with("wakelab "))
            .collect();
        assert!(!examples.is_empty(), "{sub:?}");
        for example in examples {
            let line = example.split(" # ").next().unwrap().split(" > ").next().unwrap();
            let mut words: Vec<&str> = line.split_whitespace().skip(1).collect();
            assert_eq!(&words[..sub.len()], sub, "{example}");
            words.push("--help");
            let o = wakelab(&words);
            assert!(o.status.success(), "{example}: {}", stderr(&o));
        }
    }
}
