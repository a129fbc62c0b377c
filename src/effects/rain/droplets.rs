//! One droplet running down the wall: motion (Chang eqs. 2-4), water
//! exchange (eqs. 5-6) and dirt exchange (eqs. 7-8).

use rand::Rng as _;

use super::wall::Wall;
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
    /// How it ended.
    pub outcome: End,
}

/// Chang eqs. (5-6): water the wall takes from a droplet of mass `m` in one
/// step of length `dt`. A saturated pixel (w = a) takes nothing; the transfer
/// never exceeds the pixel's free capacity nor the droplet's mass.
#[inline]
pub fn absorbed(m: f32, w: f32, a: f32, k_a: f32, dt: f32) -> f32 {
    let free = (a - w).max(0.0);
    (k_a * free / a * m * dt).min(free).min(m)
}

/// Chang eqs. (7-8): net dirt moved from droplet to wall in one step
/// (negative: the droplet dissolves dirt). `k_D = 1 - k_S`; `rate` scales
/// the whole exchange, so what one side loses the other gains.
#[inline]
pub fn deposited(s: f32, d: f32, k_s: f32, dt: f32, rate: f32) -> f32 {
    let k_d = 1.0 - k_s;
    ((k_s * s - k_d * d) * dt * rate).clamp(-d, s)
}

/// Chang eqs. (2-4): one velocity update with roughness (M_x, M_y) and
/// `xi1 ~ U[-1, 1]`. The braking terms are applied as a factor clamped at 0
/// (semi-implicit), so a rough pixel stops a droplet instead of reversing it.
#[inline]
pub fn accelerate(vx: f32, vy: f32, mx: f32, my: f32, xi1: f32, p: &RainParams) -> (f32, f32) {
    let slow = 1.0 / (p.r_max - p.r + 1.0).max(1e-3);
    // Chang eq. (2): sideways diffusion velocity from vertical roughness.
    let vx_diffuse = p.b * p.r * xi1 * my;
    // Chang eq. (3): dv_x/dt = v_x_diffuse - v_x M_x / (r_max - r + 1).
    let vx = vx * (1.0 - mx * slow).max(0.0) + vx_diffuse;
    // Chang eq. (4): dv_y/dt = g - v_y rho M_y / (r_max - r + 1).
    let vy = vy * (1.0 - p.rho * my * slow).max(0.0) + p.g;
    let speed = (vx * vx + vy * vy).sqrt();
    if speed > p.v_max {
        (vx * p.v_max / speed, vy * p.v_max / speed)
    } else {
        (vx, vy)
    }
}

/// Runs one droplet until it dries, leaves the region or hits the step cap.
/// Water and dirt move between droplet and wall; their sums are conserved
/// (dirt that runs off the region is returned in [`Trace::dirt_lost`]).
pub fn run(wall: &mut Wall, drop: &mut Droplet, p: &RainParams, rng: &mut Rng) -> Trace {
    let dt = p.dt;
    // The last pixels visited (a ring), where a drying droplet leaves its dirt.
    let mut tail = Tail {
        pixels: [usize::MAX; TAIL],
        head: 0,
    };
    let mut trace = Trace {
        steps: 0,
        end: (drop.x, drop.y),
        dirt_lost: 0.0,
        outcome: End::StepCap,
    };
    while trace.steps < p.max_steps {
        // Truncation is floor here: negative positions are rejected first.
        let (x, y) = (drop.x as usize, drop.y as usize);
        let in_grid = drop.x >= 0.0 && drop.y >= 0.0 && x < wall.cols && y < wall.rows;
        let i = if in_grid { wall.idx(x, y) } else { 0 };
        if !in_grid || wall.inside[i] == 0.0 {
            trace.dirt_lost = drop.s;
            drop.s = 0.0;
            trace.outcome = End::LeftRegion;
            return trace;
        }
        trace.end = (drop.x, drop.y);
        tail.visit(i);
        if drop.m < p.mass_min {
            spread_over(wall, &tail, drop.s);
            drop.s = 0.0;
            trace.outcome = End::Dried;
            return trace;
        }
        let water = absorbed(drop.m, wall.w[i], p.saturation, p.k_a, dt);
        drop.m -= water;
        wall.w[i] += water;
        let dirt = deposited(drop.s, wall.d[i], p.k_s, dt, 1.0);
        drop.s -= dirt;
        wall.d[i] += dirt;

        let (mx, my) = wall.roughness(i);
        let xi1: f32 = rng.random::<f32>() * 2.0 - 1.0;
        (drop.vx, drop.vy) = accelerate(drop.vx, drop.vy, mx, my, xi1, p);
        drop.x += drop.vx;
        drop.y += drop.vy;
        trace.steps += 1;
    }
    spread_over(wall, &tail, drop.s);
    drop.s = 0.0;
    trace
}

/// Pixels over which a drying droplet leaves its remaining dirt.
const TAIL: usize = 64;

/// The last [`TAIL`] distinct pixels a droplet visited, as a ring.
struct Tail {
    pixels: [usize; TAIL],
    head: usize,
}

impl Tail {
    #[inline]
    fn visit(&mut self, i: usize) {
        if self.pixels[self.head] != i {
            self.head = (self.head + 1) % TAIL;
            self.pixels[self.head] = i;
        }
    }

    /// Visited pixels, most recent first.
    fn recent(&self) -> impl Iterator<Item = usize> + '_ {
        (0..TAIL)
            .map(move |k| self.pixels[(self.head + TAIL - k) % TAIL])
            .take_while(|&i| i != usize::MAX)
    }
}

/// Leaves `dirt` along the tail, more where the droplet stopped
/// [choice: Chang removes light droplets without saying where their dirt
/// goes; dumping it on one pixel leaves dots, so it fades in over the last
/// few pixels, like the dark tip of a real run].
fn spread_over(wall: &mut Wall, tail: &Tail, dirt: f32) {
    let n = tail.recent().count();
    if n == 0 || dirt == 0.0 {
        return;
    }
    let total = (n * (n + 1) / 2) as f32;
    for (k, i) in tail.recent().enumerate() {
        wall.d[i] += dirt * (n - k) as f32 / total;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{Stream, rng};
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn water_exchange_conserves_and_respects_saturation(
            m in 0.0f32..200.0, w in 0.0f32..1.0, a in 0.01f32..1.0, k_a in 0.0f32..=1.0, dt in 0.0f32..2.0,
        ) {
            let w = w * a;
            let t = absorbed(m, w, a, k_a, dt);
            prop_assert!(t >= 0.0);
            prop_assert!(t <= m + 1e-6, "never more than the droplet has");
            prop_assert!(w + t <= a + 1e-5, "never above saturation");
            // Reference: eq. (5) Euler step when it does not overshoot.
            let euler = k_a * (a - w) / a * m * dt;
            if euler <= a - w && euler <= m {
                prop_assert!((t - euler).abs() < 1e-4);
            }
        }

        #[test]
        fn dirt_exchange_conserves_and_never_goes_negative(
            s in 0.0f32..50.0, d in 0.0f32..50.0, k_s in 0.0f32..=1.0, f in 0.0f32..=1.0,
        ) {
            let t = deposited(s, d, k_s, 0.1, f);
            prop_assert!(s - t >= -1e-6 && d + t >= -1e-6);
            // Reference eqs. (7-8): dS = -k_S S + k_D D, dD = -dS.
            let want = (k_s * s - (1.0 - k_s) * d) * 0.1 * f;
            prop_assert!((t - want.clamp(-d, s)).abs() < 1e-5);
        }
    }

    #[test]
    fn saturated_pixel_absorbs_nothing() {
        assert_eq!(absorbed(50.0, 0.3, 0.3, 0.5, 1.0), 0.0);
    }

    #[test]
    fn smooth_wall_droplet_falls_straight_down() {
        let p = RainParams::default();
        let (mut vx, mut vy) = (0.0, 0.0);
        for _ in 0..50 {
            (vx, vy) = accelerate(vx, vy, 0.0, 0.0, 1.0, &p);
        }
        assert_eq!(vx, 0.0, "no vertical roughness, no scatter (eq. 2)");
        assert!((vy - p.v_max).abs() < 1e-6, "gravity up to the speed limit");
    }

    #[test]
    fn vertical_roughness_brakes_and_scatters() {
        let p = RainParams::default();
        let (vx, vy) = accelerate(0.0, 0.8, 0.0, 0.3, 1.0, &p);
        assert!(vy < 0.8, "rho * M_y brakes the fall");
        assert!(vx > 0.0, "b r xi M_y pushes sideways");
    }

    #[test]
    fn droplet_conserves_water_and_dirt_with_the_wall() {
        let (width, height) = (32, 64);
        let luma: Vec<f32> = (0..width * height)
            .map(|i| ((i * 37) % 97) as f32)
            .collect();
        let mut wall = Wall::new(width, height, &luma, &vec![true; width * height]);
        for d in wall.d.iter_mut().zip(&wall.inside) {
            *d.0 = 2.0 * d.1;
        }
        let p = RainParams::default();
        let mut drop = Droplet {
            x: 16.5,
            y: 1.5,
            vx: 0.0,
            vy: 0.0,
            m: 8.0,
            s: 3.0,
        };
        let (water0, dirt0) = (wall.total_water() + 8.0, wall.total_dirt() + 3.0);
        let t = run(&mut wall, &mut drop, &p, &mut rng(1, Stream::Droplet, 0, 0));
        assert!(t.steps > 0);
        let water1 = wall.total_water() + drop.m as f64;
        let dirt1 = wall.total_dirt() + drop.s as f64 + t.dirt_lost as f64;
        assert!((water0 - water1).abs() < 1e-3, "{water0} vs {water1}");
        assert!((dirt0 - dirt1).abs() < 1e-3, "{dirt0} vs {dirt1}");
        assert!(t.end.1 > 1.5, "it ran downward");
    }
}
