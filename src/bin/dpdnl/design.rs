//! placeholder
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct DesignArgs {}
#[derive(clap::Args)]
pub struct TheoryArgs {}

pub fn design_main(_a: DesignArgs) -> Result<ExitCode, Box<dyn std::error::Error>> {
    Err("not implemented yet".into())
}
pub fn theory_main(_a: TheoryArgs) -> Result<ExitCode, Box<dyn std::error::Error>> {
    Err("not implemented yet".into())
}
