//! Droplets side by side on both cores, with the same result at any thread
//! count.
//!
//! The wall is cut into patches of whole columns, [`BAND`] x 2 wide. The
//! droplets of a batch (those before a diffusion round) are queued on the
//! patch of their column, in their order, and each patch runs its queue
//! alone, so patches can run in parallel. A droplet that steps out of its
//! patch is parked; once every patch is done, parked droplets resume on
//! patches shifted by one band, so the border they crossed is now in the
//! middle of a patch. This repeats
//! until every droplet has finished.
//!
//! The cut depends only on the wall's width, never on the number of threads.
//! Droplets in different patches touch different pixels, so the order they
//! run in does not matter; the only difference from running the droplets one
//! after another is that a droplet crossing a patch border finishes after the
//! others of its batch [choice: Chang runs droplets one by one; they fall at
//! the same time on a real wall].

use rayon::prelude::*;

use super::droplets::{Laws, Patch, Runner};
use super::wall::Wall;
use crate::error::Result;
use crate::progress::Progress;

/// Half a patch's width, in grid columns.
const BAND: usize = 64;

/// Runs every droplet in `runners` (in index order) to its end, and returns
/// them in index order.
///
/// # Errors
/// [`crate::Error::Cancelled`] when the progress's cancel flag is set.
pub fn run(
    wall: &mut Wall,
    mut runners: Vec<Runner>,
    laws: &Laws,
    progress: &Progress,
) -> Result<Vec<Runner>> {
    let mut done = Vec::with_capacity(runners.len());
    let mut shifted = false;
    while !runners.is_empty() {
        progress.check()?;
        let bounds = bounds(wall.cols, shifted);
        let mut queues: Vec<Vec<Runner>> = vec![Vec::new(); bounds.len() - 1];
        for r in runners.drain(..) {
            queues[patch_of(r.column().min(wall.cols - 1), shifted)].push(r);
        }
        let lanes: Vec<Lane> = wall
            .patches(&bounds)
            .into_iter()
            .zip(queues)
            .map(|(patch, queue)| Lane {
                patch,
                queue,
                next: 0,
            })
            .collect();
        let ran: Vec<Result<Vec<Runner>>> = lanes
            .into_par_iter()
            .chunks(LANES)
            .map(|mut lanes| {
                interleave(&mut lanes, laws, progress)?;
                Ok(lanes.into_iter().flat_map(|l| l.queue).collect())
            })
            .collect();
        for queue in ran {
            for r in queue? {
                match r.trace.outcome {
                    Some(_) => done.push(r),
                    None => runners.push(r),
                }
            }
        }
        runners.sort_by_key(|r| r.index);
        shifted = !shifted;
    }
    done.sort_by_key(|r| r.index);
    Ok(done)
}

/// Patches one thread runs at once, a step of each in turn: their droplets
/// are independent, so the processor overlaps their steps (one droplet's
/// step is a chain of dependent arithmetic that leaves it mostly waiting).
const LANES: usize = 2;

/// A patch and its queue of droplets.
struct Lane<'a> {
    patch: Patch<'a>,
    queue: Vec<Runner>,
    /// The droplet running now.
    next: usize,
}

/// Runs the lanes' queues (two at most) to the end, stepping their current
/// droplets in turn.
fn interleave(lanes: &mut [Lane], laws: &Laws, progress: &Progress) -> Result<()> {
    let mut finished = 0;
    loop {
        let mut busy = lanes.iter_mut().filter(|l| l.next < l.queue.len());
        match (busy.next(), busy.next()) {
            (None, _) => return Ok(()),
            (Some(a), None) => {
                a.queue[a.next].run(&mut a.patch, laws);
                a.next += 1;
                finished += 1;
            }
            (Some(a), Some(b)) => {
                let (ra, pa) = (&mut a.queue[a.next], &mut a.patch);
                let (rb, pb) = (&mut b.queue[b.next], &mut b.patch);
                loop {
                    let (going_a, going_b) = (ra.step(pa, laws), rb.step(pb, laws));
                    if !going_a || !going_b {
                        a.next += usize::from(!going_a);
                        b.next += usize::from(!going_b);
                        finished += usize::from(!going_a) + usize::from(!going_b);
                        break;
                    }
                }
            }
        }
        if finished >= 32 {
            finished = 0;
            progress.check()?;
        }
    }
}

/// The patch holding `column` among those cut at [`bounds`].
fn patch_of(column: usize, shifted: bool) -> usize {
    (column + BAND * usize::from(shifted)) / (2 * BAND)
}

/// Patch borders for a wall `cols` columns wide: every 2 bands, or every 2
/// bands offset by one.
fn bounds(cols: usize, shifted: bool) -> Vec<usize> {
    let first = if shifted { BAND } else { 2 * BAND };
    let mut bounds = vec![0];
    bounds.extend((first..cols).step_by(2 * BAND));
    bounds.push(cols);
    bounds
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_tile_the_wall_and_shift_by_a_band() {
        assert_eq!(bounds(300, false), vec![0, 128, 256, 300]);
        assert_eq!(bounds(300, true), vec![0, 64, 192, 300]);
        assert_eq!(bounds(50, false), vec![0, 50]);
        assert_eq!(bounds(50, true), vec![0, 50]);
        // A column's patch is the one whose bounds hold it.
        for shifted in [false, true] {
            let b = bounds(300, shifted);
            for c in 0..300 {
                let p = patch_of(c, shifted);
                assert!(b[p] <= c && c < b[p + 1], "column {c}, shifted {shifted}");
            }
        }
    }
}
