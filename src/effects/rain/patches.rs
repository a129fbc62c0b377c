//! Droplets side by side on both cores, with the same result at any thread
//! count.
//!
//! The wall is cut into patches of whole columns, [`BAND`] x 2 wide. The
//! droplets of a batch are queued on the patch of their column, in their
//! order, and each patch runs its queue alone, so patches can run in
//! parallel. A droplet that steps out of its patch is parked; once every
//! patch is done, parked droplets resume on patches shifted by one band, so
//! the border they crossed is now in the middle of a patch. This repeats
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
            let patch = (r.column().min(wall.cols - 1) + BAND * usize::from(shifted)) / (2 * BAND);
            queues[patch].push(r);
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
/// step is a chain of dependent operations that would leave it mostly idle).
const LANES: usize = 4;

/// A patch and its queue of droplets.
struct Lane<'a> {
    patch: Patch<'a>,
    queue: Vec<Runner>,
    /// The droplet running now.
    next: usize,
}

/// Runs the lanes' queues to the end, a step of each lane's current droplet
/// in turn.
fn interleave(lanes: &mut [Lane], laws: &Laws, progress: &Progress) -> Result<()> {
    let mut started = 0;
    loop {
        let mut active = false;
        for lane in lanes.iter_mut() {
            let Some(r) = lane.queue.get_mut(lane.next) else {
                continue;
            };
            active = true;
            if !r.step(&mut lane.patch, laws) {
                lane.next += 1;
                started += 1;
                if started % 32 == 0 {
                    progress.check()?;
                }
            }
        }
        if !active {
            return Ok(());
        }
    }
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
                let p = (c + BAND * usize::from(shifted)) / (2 * BAND);
                assert!(b[p] <= c && c < b[p + 1], "column {c}, shifted {shifted}");
            }
        }
    }
}
