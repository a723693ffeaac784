//! The estimator lab's pictures: labelled contact sheets of renders and log-log
//! convergence plots, both written as PNG and both independent of the machine's fonts
//! (text is drawn with DejaVu Sans, embedded in the binary).

pub mod font;
pub mod plot;
pub mod sheet;
