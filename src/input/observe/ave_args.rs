//! What the averaging fixes' common part (`fix`) hands to the part particular to each style
//! (`ave_time`, `ave_chunk`, `ave_histo`): the parsed common arguments and keywords
//! ([`FixArgs`], with `ave/chunk`'s [`Norm`]) and a sample's place in its Nfreq epoch
//! ([`Epoch`]). A leaf: `fix` and the style modules import it and it imports neither, so the
//! dependency runs one way, from `fix` to the styles.

use super::average::Ave;
use crate::engine::System;
use crate::engine::measure::Beyond;

/// `fix ave/chunk`'s `norm all|sample|none`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Norm {
    All,
    Sample,
    None,
}

/// The arguments and keywords every averaging fix parses ([`super::Observe::parse_fix`]), for
/// the part of the parsing particular to its style.
pub(super) struct FixArgs<'a> {
    pub(super) args: &'a [String],
    pub(super) id: &'a str,
    pub(super) style: &'a str,
    pub(super) sys: &'a System,
    pub(super) raw_values: Vec<&'a str>,
    pub(super) nevery: i64,
    pub(super) ave: Ave,
    pub(super) vector: bool,
    pub(super) format: String,
    pub(super) titles: [Option<String>; 3],
    pub(super) norm: Norm,
    pub(super) beyond: Beyond,
}

/// Where a sample falls in its fix's Nfreq epoch ([`super::Observe::accumulate`]).
#[derive(Clone, Copy)]
pub(super) struct Epoch<'a> {
    pub(super) id: &'a str,
    pub(super) step: u64,
    pub(super) first: bool,
    pub(super) done: bool,
    pub(super) nrepeat: f64,
}
