//! `impact scenes`: the shipped scenes, one name a line (stdout).
use anyhow::Result;

pub(crate) fn command() -> Result<()> {
    for name in impact_core::scene::BUILTIN {
        say!("{name}");
    }
    Ok(())
}
