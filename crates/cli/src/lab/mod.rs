//! TEMPORARY stand-ins, replaced when the lab branch merges.
pub mod plot;
pub mod sheet;
