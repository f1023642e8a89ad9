//! skillwright-core: the parts of skillwright that are worth doing in Rust.
//!
//! This crate has no Python in it; `skillwright-python` wraps it for the application.

pub mod digest;
pub mod error;
pub mod index;
pub mod mcap;
#[cfg(target_os = "linux")]
pub mod sandbox;

pub use error::{CoreError, CoreResult};

/// The version of this crate, as built.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
