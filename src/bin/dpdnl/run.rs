//! placeholder
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct RunArgs {}

pub fn main(_a: RunArgs) -> Result<ExitCode, Box<dyn std::error::Error>> {
    Err("not implemented yet".into())
}
