//! One module per subcommand; each only calls the libraries and prints.

pub(crate) mod demo;
pub(crate) mod engage;
mod engage_plots;
pub(crate) mod envelope;
pub(crate) mod gouge;
pub(crate) mod path;
pub(crate) mod simulate;
pub(crate) mod tool;
pub(crate) mod tools;
pub(crate) mod toolsize;
