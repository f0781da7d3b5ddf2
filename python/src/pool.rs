//! Threads that run simulations for [`crate::run`], kept between runs: a run hands its
//! work to an idle thread (or a new one when none is idle) and waits on a [`Task`]. A
//! thread costs some 70 µs to start here, more than a short run's whole Python share;
//! an idle one is woken in a few. Each thread runs one task at a time, so concurrent runs
//! (several Python threads) get threads of their own.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::mpsc::{channel, Sender};
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::time::Duration;

/// Work for a pooled thread: it runs, and returns what hands its result over, which the
/// thread calls once it is idle again (so the caller's next run finds this thread, and
/// the simulation it keeps: `mbfx::session::prepared`).
type Job = Box<dyn FnOnce() -> Deliver + Send + 'static>;

/// Hands a job's result to its task.
type Deliver = Box<dyn FnOnce() + Send + 'static>;

/// Threads waiting for work, by the sender that wakes each.
static IDLE: Mutex<Vec<Sender<Job>>> = Mutex::new(Vec::new());

/// The result of submitted work, once it is there: the value, or the panic it ended in.
pub struct Task<T> {
    slot: Mutex<Option<std::thread::Result<T>>>,
    ready: Condvar,
}

impl<T> Task<T> {
    /// The result, when it comes within `timeout` (taken: a second call gets None).
    pub fn wait(&self, timeout: Duration) -> Option<std::thread::Result<T>> {
        let slot = self.slot.lock().unwrap_or_else(PoisonError::into_inner);
        let (mut slot, _) = self
            .ready
            .wait_timeout_while(slot, timeout, |s| s.is_none())
            .unwrap_or_else(PoisonError::into_inner);
        slot.take()
    }
}

/// Runs `work` on a pooled thread; its result (or panic) arrives in the returned task.
pub fn submit<T: Send + 'static>(work: impl FnOnce() -> T + Send + 'static) -> Arc<Task<T>> {
    let task = Arc::new(Task {
        slot: Mutex::new(None),
        ready: Condvar::new(),
    });
    let done = task.clone();
    let job: Job = Box::new(move || {
        let result = catch_unwind(AssertUnwindSafe(work));
        Box::new(move || {
            *done.slot.lock().unwrap_or_else(PoisonError::into_inner) = Some(result);
            done.ready.notify_all();
        })
    });
    let idle = IDLE.lock().unwrap_or_else(PoisonError::into_inner).pop();
    let job = match idle {
        // A thread that has gone (it never does while the process lives) returns the job.
        Some(wake) => match wake.send(job) {
            Ok(()) => return task,
            Err(returned) => returned.0,
        },
        None => job,
    };
    std::thread::spawn(move || {
        let (wake, work) = channel::<Job>();
        let mut job = job;
        loop {
            let deliver = job();
            IDLE.lock()
                .unwrap_or_else(PoisonError::into_inner)
                .push(wake.clone());
            deliver();
            match work.recv() {
                Ok(next) => job = next,
                Err(_) => return,
            }
        }
    });
    task
}
