//! The PARAMS table: the core effects' rows and those of the sections
//! added since, joined at compile time.

use super::params::ParamSpec;

/// Every numeric parameter. Validation, `grime preset default` comments and
/// the GUI's sliders all read this table. Entries with `min == max` document
/// a switch, a name or a list (never range-checked).
pub static PARAMS: &[ParamSpec] = &ALL;

/// The tables of the preset's modules, in section order.
const PARTS: &[&[ParamSpec]] = &[
    super::params::CORE,
    super::params_dust::DUST_AND_GAMMATON,
    super::imperfections::ROWS[0],
    super::imperfections::ROWS[1],
    super::imperfections::ROWS[2],
    super::imperfections::ROWS[3],
    super::imperfections::ROWS[4],
    super::imperfections::ROWS[5],
    super::smudges::ROWS[0],
    super::smudges::ROWS[1],
    super::smudges::ROWS[2],
    super::weathering::ROWS[0],
    super::weathering::ROWS[1],
    super::weathering::ROWS[2],
    super::weathering::ROWS[3],
    super::weathering::ROWS[4],
    super::foot::ROWS,
];

// A static: the table is too large to copy into every use (clippy's
// large_const_arrays).
static ALL: [ParamSpec; rows(PARTS)] = join(PARTS);

const fn rows(parts: &[&[ParamSpec]]) -> usize {
    let (mut i, mut n) = (0, 0);
    while i < parts.len() {
        n += parts[i].len();
        i += 1;
    }
    n
}

/// The parts one after another (a `const` concatenation).
const fn join<const N: usize>(parts: &[&[ParamSpec]]) -> [ParamSpec; N] {
    let mut out = [super::params::p("", "", "", 0.0, 0.0); N];
    let (mut i, mut k) = (0, 0);
    while i < parts.len() {
        let mut j = 0;
        while j < parts[i].len() {
            out[k] = parts[i][j];
            k += 1;
            j += 1;
        }
        i += 1;
    }
    out
}
