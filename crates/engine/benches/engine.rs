//! Raw search speed of the engine, apart from any model: the deadlock
//! search over a synthetic torus, with one and two threads, with a cheap
//! successor function and with one that costs (as a model's does).
//!
//! `cargo bench -p robosim-engine --bench engine`

use robosim_engine::algo::{find_deadlock, DeadlockResult};
use robosim_engine::budget::Budget;
use robosim_engine::lts::{Event, Label, Lts, FIRST_VISIBLE};

const A: Event = FIRST_VISIBLE;
const B: Event = FIRST_VISIBLE + 1;
const C: Event = FIRST_VISIBLE + 2;

fn main() {
    divan::main();
}

/// A torus of `w × w` states with four moves each and no deadlock; with
/// `work > 0`, each successor computation also spins `work` rounds of
/// arithmetic, to stand in for a model whose successor function costs.
struct Torus(u64, u32);

impl Lts for Torus {
    type State = u64;

    fn initial(&self) -> u64 {
        0
    }

    fn successors(&self, s: &u64, out: &mut Vec<(Label, u64)>) {
        let w = self.0;
        let mut spin = *s;
        for _ in 0..self.1 {
            spin = std::hint::black_box(spin.wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(7));
        }
        std::hint::black_box(spin);
        let (x, y) = (s / w, s % w);
        out.push((Label::plain(A), ((x + 1) % w) * w + y));
        out.push((Label::plain(B), x * w + (y + 1) % w));
        out.push((Label::plain(C), ((x * 7 + 3) % w) * w + (y * 5 + 1) % w));
        out.push((Label::TAU, y * w + x));
    }
}

/// (width, work per successor call, threads).
#[divan::bench(args = [(1000, 0, 1), (1000, 0, 2), (1000, 1000, 1), (1000, 1000, 2)], sample_count = 5, sample_size = 1)]
fn torus_deadlock_search(bencher: divan::Bencher, (w, work, threads): (u64, u32, usize)) {
    let l = Torus(w, work);
    let budget = Budget::default().with_threads(threads);
    let (r, s) = find_deadlock(&l, &budget, None);
    assert_eq!(r, DeadlockResult::Free);
    eprintln!(
        "torus {w}×{w}, work {work}, {threads} thread(s): {} states, {:.1} bytes/state",
        s.states,
        s.bytes as f64 / s.states as f64
    );
    bencher.counter(divan::counter::ItemsCount::new(s.states)).bench(|| find_deadlock(&l, &budget, None).1.states);
}
