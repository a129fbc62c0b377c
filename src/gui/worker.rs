//! A background thread for long work, with cancellation and no stale
//! results.
//!
//! Every [`Worker::submit`] gets a new job id and sets the cancel flag of the
//! job before it, so a running pipeline stops at its next check. The thread
//! skips queued jobs that a newer one has replaced, and [`Worker::poll`]
//! drops any reply whose id is not the newest: a slow, stale result can never
//! overwrite a newer one. The thread calls the repaint callback whenever it
//! has something to show, so the UI wakes up without polling.
//!
//! A job may also hand over early results before its final one
//! ([`Worker::spawn_progressive`]): the preview shows a coarse pass first and
//! refines it. Early results carry the job's id and are marked
//! [`Done::partial`]; they follow the same rules (only the newest job's
//! results are returned, in the order they were made), and the job stays
//! busy, and cancellable, until its final result is in.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::error::{Error, Result};
use crate::progress::Progress;

/// Called from the worker thread when the UI should redraw.
pub type Repaint = Arc<dyn Fn() + Send + Sync>;

struct Job<J> {
    id: u64,
    input: J,
    cancel: Arc<AtomicBool>,
}

struct Reply<R> {
    id: u64,
    result: Result<R>,
    elapsed: Duration,
    partial: bool,
}

/// Where the running job is: its id, stage name and fraction done.
#[derive(Debug, Clone, Default)]
pub struct Status {
    /// Id of the job the numbers belong to.
    pub id: u64,
    /// Stage name reported by the pipeline.
    pub stage: String,
    /// Fraction done, 0..1.
    pub fraction: f32,
}

/// A finished job.
#[derive(Debug)]
pub struct Done<R> {
    /// The job's id, as returned by [`Worker::submit`].
    pub id: u64,
    /// What the job returned.
    pub result: Result<R>,
    /// Wall time the job took on the worker thread (for a partial result:
    /// from the job's start to this result).
    pub elapsed: Duration,
    /// True for an early result: the job goes on and its final result
    /// follows (unless a newer job cancels it).
    pub partial: bool,
}

/// One worker thread running jobs of type `J` that produce `R`.
pub struct Worker<J: Send + 'static, R: Send + 'static> {
    tx: Option<Sender<Job<J>>>,
    rx: Receiver<Reply<R>>,
    next_id: u64,
    /// Id and cancel flag of the newest submitted job, until its reply is in.
    pending: Option<(u64, Arc<AtomicBool>)>,
    status: Arc<Mutex<Status>>,
    thread: Option<JoinHandle<()>>,
}

impl<J: Send + 'static, R: Send + 'static> Worker<J, R> {
    /// Starts a worker thread named `name` that runs `run` on each job.
    pub fn spawn(
        name: &str,
        repaint: Repaint,
        mut run: impl FnMut(J, &Progress) -> Result<R> + Send + 'static,
    ) -> Worker<J, R> {
        Worker::spawn_progressive(name, repaint, move |job, progress, _| run(job, progress))
    }

    /// Like [`Worker::spawn`], but `run` may hand over early results through
    /// its third argument before it returns the final one. Each arrives from
    /// [`Worker::poll`] as a [`Done`] with `partial` set.
    pub fn spawn_progressive(
        name: &str,
        repaint: Repaint,
        mut run: impl FnMut(J, &Progress, &dyn Fn(R)) -> Result<R> + Send + 'static,
    ) -> Worker<J, R> {
        let (tx, job_rx) = mpsc::channel::<Job<J>>();
        let (reply_tx, rx) = mpsc::channel::<Reply<R>>();
        let status = Arc::new(Mutex::new(Status::default()));
        let thread_status = Arc::clone(&status);
        let thread = std::thread::Builder::new()
            .name(name.to_string())
            .spawn(move || {
                while let Ok(mut job) = job_rx.recv() {
                    // Skip to the newest queued job: the others are stale.
                    while let Ok(newer) = job_rx.try_recv() {
                        job = newer;
                    }
                    if job.cancel.load(Ordering::Relaxed) {
                        let _ = reply_tx.send(Reply {
                            id: job.id,
                            result: Err(Error::Cancelled),
                            elapsed: Duration::ZERO,
                            partial: false,
                        });
                        repaint();
                        continue;
                    }
                    let id = job.id;
                    let last_repaint = Mutex::new(Instant::now());
                    let report = |stage: &str, fraction: f32| {
                        if let Ok(mut s) = thread_status.lock() {
                            *s = Status {
                                id,
                                stage: stage.to_string(),
                                fraction,
                            };
                        }
                        // Progress bars move at most ~30 times a second.
                        if let Ok(mut t) = last_repaint.lock()
                            && t.elapsed() > Duration::from_millis(33)
                        {
                            *t = Instant::now();
                            repaint();
                        }
                    };
                    let start = Instant::now();
                    let progress = Progress::new(Some(&report), Some(&job.cancel));
                    let cancel = &job.cancel;
                    let emit = |early: R| {
                        // A cancelled job's early result would be dropped anyway.
                        if !cancel.load(Ordering::Relaxed) {
                            let _ = reply_tx.send(Reply {
                                id,
                                result: Ok(early),
                                elapsed: start.elapsed(),
                                partial: true,
                            });
                            repaint();
                        }
                    };
                    let result = run(job.input, &progress, &emit);
                    let elapsed = start.elapsed();
                    if reply_tx
                        .send(Reply {
                            id,
                            result,
                            elapsed,
                            partial: false,
                        })
                        .is_err()
                    {
                        break;
                    }
                    repaint();
                }
            })
            .ok();
        Worker {
            tx: Some(tx),
            rx,
            next_id: 0,
            pending: None,
            status,
            thread,
        }
    }

    /// Queues a job, cancelling the one before it. Returns the job's id.
    pub fn submit(&mut self, input: J) -> u64 {
        self.cancel();
        self.next_id += 1;
        let id = self.next_id;
        let cancel = Arc::new(AtomicBool::new(false));
        if let Ok(mut s) = self.status.lock() {
            *s = Status {
                id,
                stage: "queued".into(),
                fraction: 0.0,
            };
        }
        let sent = self.tx.as_ref().is_some_and(|tx| {
            tx.send(Job {
                id,
                input,
                cancel: Arc::clone(&cancel),
            })
            .is_ok()
        });
        if sent {
            self.pending = Some((id, cancel));
        }
        id
    }

    /// Asks the running job (if any) to stop; its result will be dropped.
    pub fn cancel(&mut self) {
        if let Some((_, flag)) = self.pending.take() {
            flag.store(true, Ordering::Relaxed);
        }
    }

    /// True while the newest job's final result is not in yet (early results
    /// do not end a job).
    pub fn is_busy(&self) -> bool {
        self.pending.is_some()
    }

    /// Id of the newest job submitted so far (0 before the first).
    pub fn latest_id(&self) -> u64 {
        self.next_id
    }

    /// Progress of the newest job.
    pub fn status(&self) -> Status {
        self.status.lock().map(|s| s.clone()).unwrap_or_default()
    }

    /// The newest job's latest result, once one is in: an early (partial)
    /// one while the job goes on, then its final one. Results of older jobs
    /// are dropped here, never returned; when several of the newest job's
    /// results are waiting, only the last is returned.
    pub fn poll(&mut self) -> Option<Done<R>> {
        let mut out = None;
        while let Ok(reply) = self.rx.try_recv() {
            let newest = self.pending.as_ref().is_some_and(|(id, _)| *id == reply.id);
            if newest {
                if !reply.partial {
                    self.pending = None;
                }
                out = Some(Done {
                    id: reply.id,
                    result: reply.result,
                    elapsed: reply.elapsed,
                    partial: reply.partial,
                });
            }
        }
        out
    }

    /// Blocks until the newest job has a result (early or final) or `timeout`
    /// passes (for tests and scripted runs; the UI uses [`Worker::poll`]).
    pub fn wait(&mut self, timeout: Duration) -> Option<Done<R>> {
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(done) = self.poll() {
                return Some(done);
            }
            if !self.is_busy() || Instant::now() >= deadline {
                return None;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }
}

impl<J: Send + 'static, R: Send + 'static> Drop for Worker<J, R> {
    fn drop(&mut self) {
        self.cancel();
        // Closing the channel ends the thread after its current job, which
        // the cancel flag cuts short; do not wait for it.
        self.tx = None;
        drop(self.thread.take());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    fn no_repaint() -> Repaint {
        Arc::new(|| {})
    }

    /// Runs until cancelled, checking like the pipeline does.
    fn endless(_: u32, p: &Progress) -> Result<u32> {
        loop {
            p.check()?;
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    #[test]
    fn a_new_job_cancels_the_running_one() {
        let mut w: Worker<u32, u32> = Worker::spawn("test", no_repaint(), |n, p| {
            if n == 0 { endless(n, p) } else { Ok(n * 10) }
        });
        w.submit(0);
        std::thread::sleep(Duration::from_millis(30));
        let second = w.submit(7);
        let done = w
            .wait(Duration::from_secs(10))
            .expect("second job finishes");
        assert_eq!(done.id, second);
        assert_eq!(done.result.unwrap(), 70);
        assert!(!w.is_busy());
    }

    #[test]
    fn a_new_job_stops_a_running_pipeline() {
        let d = crate::demo::facade(320, 240);
        let scene = crate::pipeline::Scene::new(d.photo, d.region).unwrap();
        let mut preset = crate::preset::Preset::default();
        preset.rain.layers = 200;
        let mut w: Worker<bool, bool> = Worker::spawn("test", no_repaint(), move |long, p| {
            if long {
                crate::pipeline::run(&scene, &preset, p)?;
            }
            Ok(long)
        });
        w.submit(true);
        std::thread::sleep(Duration::from_millis(100));
        assert!(w.is_busy());
        assert!(w.status().fraction < 0.5, "{:?}", w.status());
        let start = Instant::now();
        w.submit(false);
        let done = w.wait(Duration::from_secs(20)).expect("the short job runs");
        assert!(
            !done.result.unwrap(),
            "only the newest job's reply is returned"
        );
        assert!(
            start.elapsed() < Duration::from_secs(3),
            "the long run stopped in {:?}",
            start.elapsed()
        );
    }

    #[test]
    fn cancelled_pipeline_returns_cancelled_promptly() {
        let d = crate::demo::facade(320, 240);
        let scene = crate::pipeline::Scene::new(d.photo, d.region).unwrap();
        let mut preset = crate::preset::Preset::default();
        preset.rain.layers = 200;
        let flag = Arc::new(AtomicBool::new(false));
        let f2 = Arc::clone(&flag);
        let handle = std::thread::spawn(move || {
            let start = Instant::now();
            let r = crate::pipeline::run(&scene, &preset, &Progress::new(None, Some(&f2)));
            (r.map(|_| ()), start.elapsed())
        });
        std::thread::sleep(Duration::from_millis(100));
        let cancelled_at = Instant::now();
        flag.store(true, Ordering::Relaxed);
        let (r, _) = handle.join().unwrap();
        assert!(matches!(r, Err(Error::Cancelled)), "{r:?}");
        assert!(
            cancelled_at.elapsed() < Duration::from_secs(2),
            "stopped in {:?}",
            cancelled_at.elapsed()
        );
    }

    #[test]
    fn a_stale_result_never_overwrites_a_newer_one() {
        // Job 1 ignores its cancel flag and finishes late; job 2 is quick.
        let started = Arc::new(AtomicUsize::new(0));
        let s2 = Arc::clone(&started);
        let mut w: Worker<u32, u32> = Worker::spawn("test", no_repaint(), move |n, _| {
            s2.fetch_add(1, Ordering::SeqCst);
            if n == 1 {
                std::thread::sleep(Duration::from_millis(150));
            }
            Ok(n)
        });
        let first = w.submit(1);
        while started.load(Ordering::SeqCst) == 0 {
            std::thread::sleep(Duration::from_millis(1));
        }
        let second = w.submit(2);
        assert!(second > first);
        // Poll all along: the stale reply (1) arrives first and must be dropped.
        let deadline = Instant::now() + Duration::from_secs(10);
        let mut seen = Vec::new();
        while Instant::now() < deadline && seen.is_empty() {
            if let Some(d) = w.poll() {
                seen.push((d.id, d.result.unwrap()));
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        assert_eq!(seen, vec![(second, 2)]);
        // And nothing else turns up later.
        std::thread::sleep(Duration::from_millis(200));
        assert!(w.poll().is_none());
    }

    /// Polls until the worker is idle, collecting (id, partial, value).
    fn collect(w: &mut Worker<u32, u32>) -> Vec<(u64, bool, u32)> {
        let deadline = Instant::now() + Duration::from_secs(20);
        let mut seen = Vec::new();
        while Instant::now() < deadline {
            if let Some(d) = w.poll() {
                seen.push((d.id, d.partial, d.result.unwrap()));
            }
            if !w.is_busy() {
                break;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        seen
    }

    #[test]
    fn quick_result_then_full_result_arrive_in_order() {
        // The job hands over its quick pass, then waits for the test's go
        // before finishing its full pass.
        let (go_tx, go_rx) = mpsc::channel::<()>();
        let mut w: Worker<u32, u32> =
            Worker::spawn_progressive("test", no_repaint(), move |n, p, emit| {
                emit(n);
                go_rx.recv().map_err(|_| Error::Cancelled)?;
                p.check()?;
                Ok(n * 10)
            });
        let id = w.submit(4);
        let quick = w.wait(Duration::from_secs(10)).expect("the quick pass");
        assert_eq!((quick.id, quick.partial), (id, true));
        assert_eq!(quick.result.unwrap(), 4);
        assert!(w.is_busy(), "the full pass is still to come");
        assert!(w.poll().is_none());
        go_tx.send(()).unwrap();
        let full = w.wait(Duration::from_secs(10)).expect("the full pass");
        assert_eq!((full.id, full.partial), (id, false));
        assert_eq!(full.result.unwrap(), 40);
        assert!(!w.is_busy());
        assert!(w.poll().is_none());
    }

    #[test]
    fn a_new_job_cancels_the_pending_full_pass() {
        // Job 0 hands over its quick pass, then runs a full pass until it is
        // cancelled; job 7 is quick in both passes.
        let cancelled = Arc::new(AtomicUsize::new(0));
        let c2 = Arc::clone(&cancelled);
        let mut w: Worker<u32, u32> =
            Worker::spawn_progressive("test", no_repaint(), move |n, p, emit| {
                emit(n + 1);
                if n == 0 {
                    let r = endless(n, p);
                    if matches!(r, Err(Error::Cancelled)) {
                        c2.fetch_add(1, Ordering::SeqCst);
                    }
                    return r;
                }
                Ok(n * 10)
            });
        let first = w.submit(0);
        let quick = w
            .wait(Duration::from_secs(10))
            .expect("quick pass of job 0");
        assert_eq!(
            (quick.id, quick.partial, quick.result.unwrap()),
            (first, true, 1)
        );
        std::thread::sleep(Duration::from_millis(20));
        assert!(w.is_busy(), "job 0's full pass runs");
        let start = Instant::now();
        let second = w.submit(7);
        let seen = collect(&mut w);
        assert!(
            start.elapsed() < Duration::from_secs(3),
            "{:?}",
            start.elapsed()
        );
        assert_eq!(
            cancelled.load(Ordering::SeqCst),
            1,
            "job 0's full pass stopped"
        );
        // Only job 7's results, the final one last (the quick one may have
        // been overtaken by the final one between two polls).
        assert!(seen.iter().all(|&(id, _, _)| id == second), "{seen:?}");
        assert_eq!(seen.last(), Some(&(second, false, 70)), "{seen:?}");
        if seen.len() == 2 {
            assert_eq!(seen[0], (second, true, 8));
        }
        std::thread::sleep(Duration::from_millis(50));
        assert!(w.poll().is_none());
    }

    #[test]
    fn a_stale_quick_result_never_shows() {
        // Job 1 ignores its cancel flag: it finishes its quick pass after
        // job 2 was submitted; neither its quick nor its full result shows.
        let started = Arc::new(AtomicUsize::new(0));
        let s2 = Arc::clone(&started);
        let mut w: Worker<u32, u32> =
            Worker::spawn_progressive("test", no_repaint(), move |n, _, emit| {
                s2.fetch_add(1, Ordering::SeqCst);
                if n == 1 {
                    std::thread::sleep(Duration::from_millis(100));
                }
                emit(n);
                if n == 1 {
                    std::thread::sleep(Duration::from_millis(100));
                }
                Ok(n * 10)
            });
        w.submit(1);
        while started.load(Ordering::SeqCst) == 0 {
            std::thread::sleep(Duration::from_millis(1));
        }
        let second = w.submit(2);
        let seen = collect(&mut w);
        assert!(seen.iter().all(|&(id, _, _)| id == second), "{seen:?}");
        assert_eq!(seen.last(), Some(&(second, false, 20)));
        std::thread::sleep(Duration::from_millis(50));
        assert!(w.poll().is_none());
    }

    #[test]
    fn queued_stale_jobs_are_skipped() {
        let runs = Arc::new(Mutex::new(Vec::new()));
        let r2 = Arc::clone(&runs);
        let mut w: Worker<u32, u32> = Worker::spawn("test", no_repaint(), move |n, _| {
            r2.lock().unwrap().push(n);
            std::thread::sleep(Duration::from_millis(50));
            Ok(n)
        });
        for n in 1..=5 {
            w.submit(n);
        }
        let done = w.wait(Duration::from_secs(10)).unwrap();
        assert_eq!(done.result.unwrap(), 5);
        let ran = runs.lock().unwrap().clone();
        assert!(ran.len() <= 2, "ran {ran:?}");
        assert_eq!(ran.last(), Some(&5));
    }
}
