//! Order-preserving parallel map over the machine's cores (scoped std threads),
//! with a progress callback. Results do not depend on the thread count.

use std::sync::atomic::{AtomicUsize, Ordering};

/// `items.iter().map(f)` on all available cores, in input order. `progress`
/// receives `(done, total)` from the worker threads as chunks complete.
pub fn map<T: Sync, R: Send>(
    items: &[T],
    f: impl Fn(&T) -> R + Sync,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Vec<R> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).min(items.len().max(1));
    let chunk = items.len().div_ceil(threads * 16).max(1);
    let done = AtomicUsize::new(0);
    let next = AtomicUsize::new(0);
    let chunks: Vec<&[T]> = items.chunks(chunk).collect();
    let mut out: Vec<Option<Vec<R>>> = (0..chunks.len()).map(|_| None).collect();
    let results: Vec<Vec<(usize, Vec<R>)>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= chunks.len() {
                            break;
                        }
                        mine.push((i, chunks[i].iter().map(&f).collect::<Vec<R>>()));
                        let d = done.fetch_add(chunks[i].len(), Ordering::Relaxed) + chunks[i].len();
                        progress(d, items.len());
                    }
                    mine
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().expect("worker thread panicked")).collect()
    });
    for (i, r) in results.into_iter().flatten() {
        out[i] = Some(r);
    }
    out.into_iter().flat_map(|r| r.expect("every chunk computed")).collect()
}

#[cfg(test)]
mod tests {
    #[test]
    fn keeps_order() {
        let v: Vec<u64> = (0..1000).collect();
        let r = super::map(&v, |x| x * x, &|_, _| {});
        assert_eq!(r, v.iter().map(|x| x * x).collect::<Vec<_>>());
        assert!(super::map(&[] as &[u8], |x| *x, &|_, _| {}).is_empty());
    }
}
