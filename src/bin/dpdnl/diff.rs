//! placeholder
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct DiffArgs {}

pub fn main(_a: DiffArgs) -> Result<ExitCode, Box<dyn std::error::Error>> {
    Err("not implemented yet".into())
}
