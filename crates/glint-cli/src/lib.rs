//! The library behind the `glint` binary: what its subcommands do beyond parsing
//! arguments, so examples and tests can call it too.

pub mod bench;
pub mod checkpoint;
