//! A background thread for long work, with cancellation and no stale
//! results.
//!
//! Every [`Worker::submit`] gets a new job id and sets the cancel flag of the
//! job before it, so a running pipeline stops at its next check. The thread
//! skips queued jobs that a newer one has replaced, and [`Worker::poll`]
//! drops any reply whose id is not the newest: a slow, stale result can never
//! overwrite a newer one. The thread calls the repaint callback whenever it
//! has something to show, so the UI wakes up without polling.

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
    /// Wall time the job took on the worker thread.
    pub elapsed: Duration,
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
        run: impl Fn(J, &Progress) -> Result<R> + Send + 'static,
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
                        });
                        repaint();
                        continue;
                    }
                    let id = job.id;
                    let last_repaint = Mutex::new(Instant::now());
                    let report = |stage: &str, fraction: f32| {
                        if let Ok(mut s) = thread_status.lock() {
                            *s = Status { id, stage: stage.to_string(), fraction };
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
                    let result = run(job.input, &progress);
                    let elapsed = start.elapsed();
                    if reply_tx.send(Reply { id, result, elapsed }).is_err() {
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
            *s = Status { id, stage: "queued".into(), fraction: 0.0 };
        }
        let sent = self.tx.as_ref().is_some_and(|tx| {
            tx.send(Job { id, input, cancel: Arc::clone(&cancel) }).is_ok()
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

    /// True while the newest job has not replied yet.
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

    /// The newest job's reply, once it is in. Replies of older jobs are
    /// dropped here, never returned.
    pub fn poll(&mut self) -> Option<Done<R>> {
        let mut out = None;
        while let Ok(reply) = self.rx.try_recv() {
            let newest = self.pending.as_ref().is_some_and(|(id, _)| *id == reply.id);
            if newest {
                self.pending = None;
                out = Some(Done { id: reply.id, result: reply.result, elapsed: reply.elapsed });
            }
        }
        out
    }

    /// Blocks until the newest job has replied or `timeout` passes (for tests
    /// and scripted runs; the UI uses [`Worker::poll`]).
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
            if n == 0 {
                endless(n, p)
            } else {
                Ok(n * 10)
            }
        });
        w.submit(0);
        std::thread::sleep(Duration::from_millis(30));
        let second = w.submit(7);
        let done = w.wait(Duration::from_secs(10)).expect("second job finishes");
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
        assert!(!done.result.unwrap(), "only the newest job's reply is returned");
        assert!(start.elapsed() < Duration::from_secs(3), "the long run stopped in {:?}", start.elapsed());
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
        assert!(cancelled_at.elapsed() < Duration::from_secs(2), "stopped in {:?}", cancelled_at.elapsed());
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
