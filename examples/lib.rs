//! wakelab's library-level examples: each calls the pipeline's stages (spec Fig. 2.1) as plain
//! functions from typed input to typed output. Run one with
//! `cargo run --release --example sigma0_image`.
