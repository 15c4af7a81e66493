//! One module per subcommand, with its arguments; each only calls the libraries and prints.
//! The argument groups several share are in `crate::cli`, which knows no command.

pub(crate) mod demo;
pub(crate) mod engage;
pub(crate) mod envelope;
pub(crate) mod forces;
pub(crate) mod gouge;
pub(crate) mod path;
mod plots;
pub(crate) mod report;
pub(crate) mod schedule;
pub(crate) mod simulate;
pub(crate) mod tool;
pub(crate) mod tools;
pub(crate) mod toolsize;
pub(crate) mod verify;
