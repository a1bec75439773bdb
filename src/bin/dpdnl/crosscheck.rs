//! placeholder
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct CrosscheckArgs {}

pub fn main(_a: CrosscheckArgs) -> Result<ExitCode, Box<dyn std::error::Error>> {
    Err("not implemented yet".into())
}
