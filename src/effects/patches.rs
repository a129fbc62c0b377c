//! Particles side by side on every core, with the same result at any
//! thread count: the scheduler the rain's droplets run on, for any particle
//! that moves over a grid and changes only the pixels it stands on.
//!
//! The space is cut into patches of whole columns, `band` x 2 wide. The
//! particles of a batch are queued on the patch of their column, in their
//! order, and each patch runs its queue alone, so patches can run in
//! parallel. A particle that steps out of its patch is parked; once every
//! patch is done, parked particles resume on patches shifted by one band, so
//! the border they crossed is now in the middle of a patch. This repeats
//! until every particle has ended.
//!
//! The cut depends only on the space's width, never on the number of
//! threads. Particles in different patches touch different pixels, so the
//! order they run in does not matter; the only difference from running the
//! particles one after another is that a particle crossing a patch border
//! ends after the others of its batch [choice: Chang runs droplets one by
//! one; they fall at the same time on a real wall].

use rayon::prelude::*;

use crate::error::Result;
use crate::progress::Progress;

/// A particle that steps within a patch and may leave it.
pub trait Particle: Send {
    /// The part of the space one particle queue owns while it runs: whole
    /// columns to write, and whatever is shared read-only.
    type Patch<'a>: Send;
    /// Constants of its steps, shared by every particle.
    type Laws: Sync;

    /// Its number in the batch: particles end in this order.
    fn index(&self) -> usize;
    /// The column it stands on (clamped into the space by the scheduler).
    fn column(&self) -> usize;
    /// Whether it has ended (rather than being parked).
    fn ended(&self) -> bool;
    /// One step in `patch`; false once it has ended or left the patch.
    fn step(&mut self, patch: &mut Self::Patch<'_>, laws: &Self::Laws) -> bool;
}

/// A space particles of type `P` run in.
pub trait Space<P: Particle> {
    /// Its width in columns.
    fn columns(&self) -> usize;
    /// The space cut at columns `bounds` (ascending, from 0 to
    /// [`Space::columns`]) into patches that may run side by side.
    fn patches(&mut self, bounds: &[usize]) -> Vec<P::Patch<'_>>;
}

/// Runs every particle of `particles` (in index order) to its end in
/// `space`, on patches `2 * band` columns wide, and returns them in index
/// order.
///
/// # Errors
/// [`crate::Error::Cancelled`] when the progress's cancel flag is set.
pub fn run<P: Particle, S: Space<P>>(
    space: &mut S,
    particles: Vec<P>,
    laws: &P::Laws,
    band: usize,
    progress: &Progress,
) -> Result<Vec<P>> {
    let band = band.max(1);
    let cols = space.columns();
    let mut done = Vec::with_capacity(particles.len());
    let mut shifted = false;
    let mut queues = empty_queues(cols, band, shifted);
    for p in particles {
        queues[patch_of(p.column().min(cols - 1), band, shifted)].push(p);
    }
    while queues.iter().any(|q| !q.is_empty()) {
        progress.check()?;
        let lanes: Vec<Lane<P>> = space
            .patches(&bounds(cols, band, shifted))
            .into_iter()
            .zip(queues)
            .map(|(patch, queue)| Lane {
                patch,
                queue,
                next: 0,
            })
            .collect();
        let ran: Vec<Result<Vec<Vec<P>>>> = lanes
            .into_par_iter()
            .chunks(LANES)
            .map(|mut lanes| {
                interleave(&mut lanes, laws, progress)?;
                Ok(lanes.into_iter().map(|l| l.queue).collect())
            })
            .collect();
        // Parked particles queue on the shifted patches, each queue in
        // index order (sorted queue by queue: cheaper than sorting all).
        shifted = !shifted;
        queues = empty_queues(cols, band, shifted);
        for lanes in ran {
            for p in lanes?.into_iter().flatten() {
                if p.ended() {
                    done.push(p);
                } else {
                    queues[patch_of(p.column().min(cols - 1), band, shifted)].push(p);
                }
            }
        }
        let parked: usize = queues.iter().map(Vec::len).sum();
        let sort = |queue: &mut Vec<P>| queue.sort_by_key(P::index);
        match parked >= MANY {
            true => queues.par_iter_mut().for_each(sort),
            false => queues.iter_mut().for_each(sort),
        }
    }
    match done.len() >= MANY {
        true => Ok(in_index_order(done)),
        false => {
            done.sort_by_key(P::index);
            Ok(done)
        }
    }
}

/// Particles worth the set-up of sorting on every core, or by keys: below
/// this, a plain sort is faster (the rain's small batches).
const MANY: usize = 4096;

/// `particles` sorted by index, stably: their keys are sorted, then each
/// particle is moved once to its place (cheaper than a sort that moves
/// whole particles several times).
fn in_index_order<P: Particle>(particles: Vec<P>) -> Vec<P> {
    let mut keys: Vec<(usize, usize)> = particles
        .iter()
        .enumerate()
        .map(|(at, p)| (p.index(), at))
        .collect();
    keys.sort_unstable();
    let mut slots: Vec<Option<P>> = particles.into_iter().map(Some).collect();
    keys.iter()
        .filter_map(|&(_, at)| slots[at].take())
        .collect()
}

/// An empty queue per patch.
fn empty_queues<P>(cols: usize, band: usize, shifted: bool) -> Vec<Vec<P>> {
    (1..bounds(cols, band, shifted).len())
        .map(|_| Vec::new())
        .collect()
}

/// Patches one thread runs at once, a step of each in turn: their particles
/// are independent, so the processor overlaps their steps (one step is
/// often a chain of dependent arithmetic that leaves it mostly waiting).
const LANES: usize = 2;

/// A patch and its queue of particles.
struct Lane<'a, P: Particle> {
    patch: P::Patch<'a>,
    queue: Vec<P>,
    /// The particle running now.
    next: usize,
}

/// Runs the lanes' queues (two at most) to the end, stepping their current
/// particles in turn.
fn interleave<P: Particle>(
    lanes: &mut [Lane<P>],
    laws: &P::Laws,
    progress: &Progress,
) -> Result<()> {
    let mut finished = 0;
    loop {
        let mut busy = lanes.iter_mut().filter(|l| l.next < l.queue.len());
        match (busy.next(), busy.next()) {
            (None, _) => return Ok(()),
            (Some(a), None) => {
                let p = &mut a.queue[a.next];
                while p.step(&mut a.patch, laws) {}
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
fn patch_of(column: usize, band: usize, shifted: bool) -> usize {
    (column + band * usize::from(shifted)) / (2 * band)
}

/// Patch borders for a space `cols` columns wide: every 2 bands, or every 2
/// bands offset by one.
fn bounds(cols: usize, band: usize, shifted: bool) -> Vec<usize> {
    let first = if shifted { band } else { 2 * band };
    let mut bounds = vec![0];
    bounds.extend((first..cols).step_by(2 * band));
    bounds.push(cols);
    bounds
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_tile_the_space_and_shift_by_a_band() {
        assert_eq!(bounds(300, 64, false), vec![0, 128, 256, 300]);
        assert_eq!(bounds(300, 64, true), vec![0, 64, 192, 300]);
        assert_eq!(bounds(50, 64, false), vec![0, 50]);
        assert_eq!(bounds(50, 64, true), vec![0, 50]);
        // A column's patch is the one whose bounds hold it.
        for shifted in [false, true] {
            let b = bounds(300, 64, shifted);
            for c in 0..300 {
                let p = patch_of(c, 64, shifted);
                assert!(b[p] <= c && c < b[p + 1], "column {c}, shifted {shifted}");
            }
        }
    }

    /// A line of cells, each counting the walkers that stood on it.
    struct Line(Vec<u32>);

    /// The cells `first..first + cells.len()` of a [`Line`].
    struct Cells<'a> {
        first: usize,
        cells: &'a mut [u32],
    }

    impl Space<Walker> for Line {
        fn columns(&self) -> usize {
            self.0.len()
        }
        fn patches(&mut self, bounds: &[usize]) -> Vec<Cells<'_>> {
            let mut rest = &mut self.0[..];
            bounds
                .windows(2)
                .map(|pair| {
                    let (cells, tail) = std::mem::take(&mut rest).split_at_mut(pair[1] - pair[0]);
                    rest = tail;
                    Cells {
                        first: pair[0],
                        cells,
                    }
                })
                .collect()
        }
    }

    /// Walks `steps` cells, bumping each cell it stands on and turning
    /// where the count is odd, so the result depends on who came first.
    #[derive(Debug, Clone, PartialEq)]
    struct Walker {
        index: usize,
        x: usize,
        right: bool,
        steps: u32,
        gone: bool,
    }

    impl Particle for Walker {
        type Patch<'a> = Cells<'a>;
        type Laws = usize;

        fn index(&self) -> usize {
            self.index
        }
        fn column(&self) -> usize {
            self.x
        }
        fn ended(&self) -> bool {
            self.steps == 0 || self.gone
        }
        fn step(&mut self, patch: &mut Cells<'_>, width: &usize) -> bool {
            if self.ended() {
                return false;
            }
            let Some(j) = self
                .x
                .checked_sub(patch.first)
                .filter(|&j| j < patch.cells.len())
            else {
                return false; // parked
            };
            patch.cells[j] += 1;
            self.right ^= patch.cells[j] % 2 == 1;
            self.steps -= 1;
            match (self.right, self.x) {
                (false, 0) => self.gone = true,
                (false, _) => self.x -= 1,
                (true, x) if x + 1 == *width => self.gone = true,
                (true, _) => self.x += 1,
            }
            true
        }
    }

    fn walk(threads: usize) -> (Vec<u32>, Vec<Walker>) {
        let width = 300;
        let walkers: Vec<Walker> = (0..400)
            .map(|i| Walker {
                index: i,
                x: (i * 7919) % width,
                right: i % 3 == 0,
                steps: 50 + (i % 200) as u32,
                gone: false,
            })
            .collect();
        let mut line = Line(vec![0; width]);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let done = pool
            .install(|| run(&mut line, walkers, &width, 8, &Progress::none()))
            .unwrap();
        (line.0, done)
    }

    #[test]
    fn the_same_at_one_two_and_three_threads() {
        let (cells, done) = walk(1);
        assert_eq!(done.len(), 400);
        assert!(done.iter().all(Walker::ended));
        assert!(done.windows(2).all(|w| w[0].index < w[1].index));
        assert!(done.iter().any(|w| w.gone), "some walked off the line");
        // Every step bumped one cell.
        let steps: u32 = (0..400).map(|i| 50 + (i % 200) as u32).sum();
        let left: u32 = done.iter().map(|w| w.steps).sum();
        assert_eq!(cells.iter().sum::<u32>(), steps - left);
        for threads in [2, 3] {
            assert_eq!(walk(threads), (cells.clone(), done.clone()), "{threads}");
        }
    }
}
