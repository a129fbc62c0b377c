//! One droplet running down the wall: motion (Chang eqs. 2-4), water
//! exchange (eqs. 5-6) and dirt exchange (eqs. 7-8).
//!
//! A droplet runs inside a [`Patch`]: a band of whole columns of the wall
//! that no other thread touches meanwhile. When it steps out of its patch it
//! is parked, and resumes later in the patch that holds its new column
//! (see [`crate::effects::patches`]).

use rand::Rng as _;

use super::wall::{Patch, Wall};
use crate::effects::patches::{Particle, Space};
use crate::effects::roughness;
use crate::preset::RainParams;
use crate::random::Rng;

/// A water droplet on the padded grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Droplet {
    /// Position, padded grid pixels (sub-pixel).
    pub x: f32,
    /// Position, padded grid pixels; y grows downward.
    pub y: f32,
    /// Velocity, pixels per step.
    pub vx: f32,
    /// Velocity, pixels per step.
    pub vy: f32,
    /// Mass m (water).
    pub m: f32,
    /// Dissolved dirt S.
    pub s: f32,
}

/// How a droplet's run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// It lost its water and left its dirt where it stopped.
    Dried,
    /// It ran out of the region; its dirt left the wall with it.
    LeftRegion,
    /// It hit the step cap.
    StepCap,
}

/// What one droplet did.
#[derive(Debug, Clone, Copy)]
pub struct Trace {
    /// Steps taken.
    pub steps: u32,
    /// Last position inside the region.
    pub end: (f32, f32),
    /// Dirt carried off the region.
    pub dirt_lost: f32,
    /// How it ended; `None` while it is still running.
    pub outcome: Option<End>,
}

/// The per-step laws of one rainfall, with the preset's constants folded.
#[derive(Debug, Clone, Copy)]
pub struct Laws {
    saturation: f32,
    /// k_a dt / a (eq. 5).
    absorb: f32,
    /// k_S dt (eq. 7).
    release: f32,
    /// k_D dt = (1 - k_S) dt (eq. 8).
    dissolve: f32,
    /// 1 / (r_max - r + 1) (eqs. 3-4).
    slow: f32,
    /// rho / (r_max - r + 1) (eq. 4).
    slow_y: f32,
    /// b r (eq. 2).
    scatter: f32,
    g: f32,
    v_max: f32,
    mass_min: f32,
    max_steps: u32,
}

impl Laws {
    /// The laws for preset `p`.
    pub fn new(p: &RainParams) -> Laws {
        let slow = 1.0 / (p.r_max - p.r + 1.0).max(1e-3);
        Laws {
            saturation: p.saturation,
            absorb: p.k_a * p.dt / p.saturation,
            release: p.k_s * p.dt,
            dissolve: (1.0 - p.k_s) * p.dt,
            slow,
            slow_y: p.rho * slow,
            scatter: p.b * p.r,
            g: p.g,
            v_max: p.v_max,
            mass_min: p.mass_min,
            max_steps: p.max_steps,
        }
    }

    /// Chang eqs. (5-6): water the wall takes from a droplet of mass `m` in
    /// one step. A saturated pixel (w = a) takes nothing; the transfer never
    /// exceeds the pixel's free capacity nor the droplet's mass.
    #[inline(always)]
    pub fn absorbed(&self, m: f32, w: f32) -> f32 {
        let free = (self.saturation - w).max(0.0);
        (self.absorb * free * m).min(free).min(m)
    }

    /// Chang eqs. (7-8): net dirt moved from droplet (S = `s`) to wall
    /// (D = `d`) in one step; negative when the droplet dissolves dirt. What
    /// one side loses the other gains, and neither goes below zero.
    #[inline(always)]
    pub fn deposited(&self, s: f32, d: f32) -> f32 {
        (self.release * s - self.dissolve * d).clamp(-d, s)
    }

    /// Chang eqs. (2-4): one velocity update on a pixel of roughness
    /// (M_x, M_y) with `xi1 ~ U[-1, 1]`, then the speed limit v_max. The
    /// braking terms are applied as a factor clamped at 0 (semi-implicit),
    /// so a rough pixel stops a droplet instead of reversing it.
    #[inline(always)]
    pub fn accelerate(&self, vx: f32, vy: f32, mx: f32, my: f32, xi1: f32) -> (f32, f32) {
        // Chang eq. (2): sideways diffusion velocity b r xi1 M_y.
        // Chang eq. (3): dv_x/dt = v_x_diffuse - v_x M_x / (r_max - r + 1).
        let vx = vx * (1.0 - mx * self.slow).max(0.0) + self.scatter * my * xi1;
        // Chang eq. (4): dv_y/dt = g - v_y rho M_y / (r_max - r + 1).
        let vy = vy * (1.0 - my * self.slow_y).max(0.0) + self.g;
        let k = (self.v_max / (vx * vx + vy * vy).sqrt()).min(1.0);
        (vx * k, vy * k)
    }
}

/// A droplet that has started and may be parked between patches.
#[derive(Debug, Clone)]
pub struct Runner {
    /// The droplet's number in its rainfall.
    pub index: usize,
    /// Where it started (padded grid).
    pub start: (f32, f32),
    /// Its state.
    pub drop: Droplet,
    /// What it has done so far.
    pub trace: Trace,
    rng: Rng,
    tail: Tail,
}

impl Runner {
    /// A droplet about to take its first step, drawing its scatter from `rng`.
    pub fn new(index: usize, drop: Droplet, rng: Rng) -> Runner {
        Runner {
            index,
            start: (drop.x, drop.y),
            drop,
            trace: Trace {
                steps: 0,
                end: (drop.x, drop.y),
                dirt_lost: 0.0,
                outcome: None,
            },
            rng,
            tail: Tail::default(),
        }
    }

    /// The padded grid column the droplet is in.
    pub fn column(&self) -> usize {
        self.drop.x.max(0.0) as usize
    }

    /// Runs until the droplet dries, leaves the region, hits the step cap
    /// (then [`Trace::outcome`] is set) or leaves the patch (parked, to be
    /// resumed in another). Water and dirt move between droplet and wall;
    /// their sums are conserved (dirt that runs off the region is returned
    /// in [`Trace::dirt_lost`]).
    pub fn run(&mut self, patch: &mut Patch, laws: &Laws) {
        while self.step(patch, laws) {}
    }

    /// One step of [`Runner::run`]; false once the droplet has ended or
    /// left the patch.
    #[inline(always)]
    pub fn step(&mut self, patch: &mut Patch, laws: &Laws) -> bool {
        let drop = &mut self.drop;
        let trace = &mut self.trace;
        if trace.steps >= laws.max_steps {
            self.tail.spread(patch, drop.s);
            drop.s = 0.0;
            trace.outcome = Some(End::StepCap);
            return false;
        }
        let rows = patch.rows;
        // Truncation is floor here: negative positions are rejected first.
        let (x, y) = (drop.x as usize, drop.y as usize);
        let in_grid = drop.x >= 0.0 && drop.y >= 0.0 && x < patch.inside.len() / rows && y < rows;
        let i = if in_grid { x * rows + y } else { 0 };
        if !in_grid || patch.inside[i] == 0.0 {
            trace.dirt_lost = drop.s;
            drop.s = 0.0;
            trace.outcome = Some(End::LeftRegion);
            return false;
        }
        let Some(j) = i.checked_sub(patch.first).filter(|&j| j < patch.w.len()) else {
            // Its last pixels may belong to a patch running meanwhile.
            self.tail = Tail::default();
            return false;
        };
        trace.end = (drop.x, drop.y);
        self.tail.visit(i as u32);
        if drop.m < laws.mass_min {
            self.tail.spread(patch, drop.s);
            drop.s = 0.0;
            trace.outcome = Some(End::Dried);
            return false;
        }
        let water = laws.absorbed(drop.m, patch.w[j]);
        drop.m -= water;
        patch.w[j] += water;
        let dirt = laws.deposited(drop.s, patch.d[j]);
        drop.s -= dirt;
        patch.d[j] += dirt;

        let (mx, my) = roughness::at(patch.b, i, rows, 1);
        let xi1: f32 = self.rng.random::<f32>() * 2.0 - 1.0;
        (drop.vx, drop.vy) = laws.accelerate(drop.vx, drop.vy, mx, my, xi1);
        drop.x += drop.vx;
        drop.y += drop.vy;
        trace.steps += 1;
        true
    }
}

impl Particle for Runner {
    type Patch<'a> = Patch<'a>;
    type Laws = Laws;

    fn index(&self) -> usize {
        self.index
    }
    fn column(&self) -> usize {
        Runner::column(self)
    }
    fn ended(&self) -> bool {
        self.trace.outcome.is_some()
    }
    #[inline(always)]
    fn step(&mut self, patch: &mut Patch<'_>, laws: &Laws) -> bool {
        Runner::step(self, patch, laws)
    }
}

impl Space<Runner> for Wall {
    fn columns(&self) -> usize {
        self.cols
    }
    fn patches(&mut self, bounds: &[usize]) -> Vec<Patch<'_>> {
        Wall::patches(self, bounds)
    }
}

/// Pixels over which a drying droplet leaves its remaining dirt.
const TAIL: usize = 64;

/// The last [`TAIL`] distinct pixels a droplet visited (storage indices), as
/// a ring.
#[derive(Debug, Clone)]
struct Tail {
    pixels: [u32; TAIL],
    head: usize,
}

impl Default for Tail {
    fn default() -> Tail {
        Tail {
            pixels: [u32::MAX; TAIL],
            head: 0,
        }
    }
}

impl Tail {
    #[inline]
    fn visit(&mut self, i: u32) {
        self.head = (self.head + usize::from(self.pixels[self.head] != i)) % TAIL;
        self.pixels[self.head] = i;
    }

    /// Visited pixels, most recent first.
    fn recent(&self) -> impl Iterator<Item = usize> + '_ {
        (0..TAIL)
            .map(move |k| self.pixels[(self.head + TAIL - k) % TAIL])
            .take_while(|&i| i != u32::MAX)
            .map(|i| i as usize)
    }

    /// Leaves `dirt` along the tail, more where the droplet stopped
    /// [choice: Chang removes light droplets without saying where their dirt
    /// goes; dumping it on one pixel leaves dots, so it fades in over the
    /// last few pixels, like the dark tip of a real run].
    fn spread(&self, patch: &mut Patch, dirt: f32) {
        let n = self.recent().count();
        if n == 0 || dirt == 0.0 {
            return;
        }
        let total = (n * (n + 1) / 2) as f32;
        for (k, i) in self.recent().enumerate() {
            patch.d[i - patch.first] += dirt * (n - k) as f32 / total;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::RowMajor;
    use crate::random::{Stream, rng};
    use proptest::prelude::*;

    fn laws(k_a: f32, a: f32, dt: f32, k_s: f32) -> Laws {
        Laws::new(&RainParams {
            k_a,
            saturation: a,
            dt,
            k_s,
            ..RainParams::default()
        })
    }

    proptest! {
        #[test]
        fn water_exchange_conserves_and_respects_saturation(
            m in 0.0f32..200.0, w in 0.0f32..1.0, a in 0.01f32..1.0, k_a in 0.0f32..=1.0, dt in 0.0f32..2.0,
        ) {
            let w = w * a;
            let t = laws(k_a, a, dt, 0.7).absorbed(m, w);
            prop_assert!(t >= 0.0);
            prop_assert!(t <= m + 1e-6, "never more than the droplet has");
            prop_assert!(w + t <= a + 1e-5, "never above saturation");
            // Reference: eq. (5) Euler step when it does not overshoot.
            let euler = k_a * (a - w) / a * m * dt;
            if euler <= a - w && euler <= m {
                prop_assert!((t - euler).abs() < 1e-4 * (1.0 + euler));
            }
        }

        #[test]
        fn dirt_exchange_conserves_and_never_goes_negative(
            s in 0.0f32..50.0, d in 0.0f32..50.0, k_s in 0.0f32..=1.0,
        ) {
            let t = laws(0.5, 0.3, 0.1, k_s).deposited(s, d);
            prop_assert!(s - t >= -1e-6 && d + t >= -1e-6);
            // Reference eqs. (7-8): dS = -k_S S + k_D D, dD = -dS.
            let want = (k_s * s - (1.0 - k_s) * d) * 0.1;
            prop_assert!((t - want.clamp(-d, s)).abs() < 1e-5);
        }

        #[test]
        fn velocity_update_matches_eqs_2_to_4(
            vx in -1.0f32..1.0, vy in 0.0f32..1.0, mx in 0.0f32..1.0, my in 0.0f32..1.0,
            xi1 in -1.0f32..=1.0,
        ) {
            let p = RainParams { r: 60.0, v_max: 10.0, ..RainParams::default() };
            let (ax, ay) = Laws::new(&p).accelerate(vx, vy, mx, my, xi1);
            // Reference: one Euler step of eqs. (2-4) with dt = 1, braking clamped at 0.
            let slow = 1.0 / (p.r_max - p.r + 1.0);
            let want_x = vx * (1.0 - mx * slow).max(0.0) + p.b * p.r * xi1 * my;
            let want_y = vy * (1.0 - p.rho * my * slow).max(0.0) + p.g;
            prop_assert!((ax - want_x).abs() < 1e-5, "{ax} vs {want_x}");
            prop_assert!((ay - want_y).abs() < 1e-5, "{ay} vs {want_y}");
        }
    }

    #[test]
    fn saturated_pixel_absorbs_nothing() {
        assert_eq!(laws(0.5, 0.3, 1.0, 0.7).absorbed(50.0, 0.3), 0.0);
    }

    #[test]
    fn smooth_wall_droplet_falls_straight_down() {
        let p = RainParams::default();
        let laws = Laws::new(&p);
        let (mut vx, mut vy) = (0.0, 0.0);
        for _ in 0..50 {
            (vx, vy) = laws.accelerate(vx, vy, 0.0, 0.0, 1.0);
        }
        assert_eq!(vx, 0.0, "no vertical roughness, no scatter (eq. 2)");
        assert!((vy - p.v_max).abs() < 1e-6, "gravity up to the speed limit");
    }

    #[test]
    fn vertical_roughness_brakes_and_scatters() {
        let p = RainParams::default();
        let (vx, vy) = Laws::new(&p).accelerate(0.0, 0.8, 0.0, 0.3, 1.0);
        assert!(vy < 0.8, "rho * M_y brakes the fall");
        assert!(vx > 0.0, "b r xi M_y pushes sideways");
    }

    #[test]
    fn speed_is_capped_at_v_max_keeping_direction() {
        let p = RainParams::default();
        let (vx, vy) = Laws::new(&p).accelerate(0.6, 0.9, 0.0, 0.0, 0.0);
        assert!(((vx * vx + vy * vy).sqrt() - p.v_max).abs() < 1e-6);
        assert!((vx / vy - 0.6 / (0.9 + p.g)).abs() < 1e-6);
    }

    /// A textured 32 x 64 wall with 2 units of dirt everywhere.
    fn dirty_wall() -> Wall {
        let (width, height) = (32, 64);
        let luma = RowMajor::from_fn(width, height, |x, y| ((y * width + x) * 37 % 97) as f32);
        let mut wall = Wall::new(&luma, &RowMajor::filled(width, height, true));
        for d in wall.d.iter_mut().zip(&wall.inside) {
            *d.0 = 2.0 * d.1;
        }
        wall
    }

    fn droplet(x: f32) -> Droplet {
        Droplet {
            x,
            y: 1.5,
            vx: 0.0,
            vy: 0.0,
            m: 8.0,
            s: 3.0,
        }
    }

    #[test]
    fn droplet_conserves_water_and_dirt_with_the_wall() {
        let mut wall = dirty_wall();
        let p = RainParams::default();
        let (water0, dirt0) = (wall.total_water() + 8.0, wall.total_dirt() + 3.0);
        let mut runner = Runner::new(0, droplet(16.5), rng(1, Stream::Droplet, 0, 0));
        let cols = wall.cols;
        runner.run(&mut wall.patches(&[0, cols])[0], &Laws::new(&p));
        let t = runner.trace;
        assert!(t.steps > 0 && t.outcome.is_some());
        let water1 = wall.total_water() + runner.drop.m as f64;
        let dirt1 = wall.total_dirt() + runner.drop.s as f64 + t.dirt_lost as f64;
        assert!((water0 - water1).abs() < 1e-3, "{water0} vs {water1}");
        assert!((dirt0 - dirt1).abs() < 1e-3, "{dirt0} vs {dirt1}");
        assert!(t.end.1 > 1.5, "it ran downward");
    }

    #[test]
    fn a_parked_droplet_resumes_where_it_stopped_as_if_never_parked() {
        // Run once across the whole wall, and once in two halves with the
        // droplet parked at the border: same path, same wall, except that
        // the parked one forgets its tail (so compare one that runs off).
        let p = RainParams {
            mass_max: 1e6,
            b: 0.2,
            ..RainParams::default()
        };
        let laws = Laws::new(&p);
        let mut whole = dirty_wall();
        let cols = whole.cols;
        let start = droplet(16.5);
        let mut a = Runner::new(0, start, rng(2, Stream::Droplet, 0, 0));
        a.drop.m = 1e5;
        a.run(&mut whole.patches(&[0, cols])[0], &laws);
        assert_eq!(a.trace.outcome, Some(End::LeftRegion));

        let mut split = dirty_wall();
        let mut b = Runner::new(0, start, rng(2, Stream::Droplet, 0, 0));
        b.drop.m = 1e5;
        let mut parked = 0;
        while b.trace.outcome.is_none() {
            let mut patches = split.patches(&[0, 16, cols]);
            b.run(&mut patches[usize::from(b.column() >= 16)], &laws);
            parked += usize::from(b.trace.outcome.is_none());
        }
        assert!(parked > 0, "the droplet crossed the border");
        assert_eq!(a.drop, b.drop);
        assert_eq!(a.trace.steps, b.trace.steps);
        assert_eq!(whole.w, split.w);
        assert_eq!(whole.d, split.d);
    }
}
