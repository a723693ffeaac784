//! TEMPORARY stand-in.
use anyhow::Result;
use std::path::Path;
/// Stand-in.
pub fn convergence_plot(_path: &Path, _title: &str, _y: &str, _series: &[(String, Vec<(f64, f64)>)]) -> Result<()> {
    Ok(())
}
