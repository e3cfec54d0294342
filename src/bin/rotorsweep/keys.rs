//! `rotorsweep keys`: the key reference of scene files, as Markdown on stdout.
//!
//! In: nothing. Out: the text of `docs/scene-keys.md` (every key the parser accepts, with type,
//! units, default, allowed values and meaning), generated from the parser's schema
//! ([`rotorsweep::scene::keys`]).

/// Arguments of `rotorsweep keys`.
#[derive(clap::Args)]
pub struct Args {}

/// Prints the reference.
pub fn run(_: &Args) -> Result<(), crate::error::CliError> {
    print!("{}", rotorsweep::scene::keys::markdown());
    Ok(())
}
