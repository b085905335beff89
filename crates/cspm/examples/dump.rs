//! Prints a CSPm file's diagnostics, the values of its `test*` names and
//! the sizes of the LTSs of the processes named on the command line.
fn main() {
    // Deep recursions (long sequences, big terms) need a big stack.
    std::thread::Builder::new().stack_size(1 << 30).spawn(run).unwrap().join().unwrap();
}

fn run() {
    let mut args = std::env::args().skip(1);
    let path = std::path::PathBuf::from(args.next().expect("a .csp file"));
    let bytes = std::fs::read(&path).expect("readable");
    let text = String::from_utf8_lossy(&bytes);
    let names = robosim_cspm::NoNames;
    let dir = path.parent().map(|p| p.to_path_buf()).unwrap_or_default();
    let load = |f: &str| std::fs::read(dir.join(f)).ok().map(|b| String::from_utf8_lossy(&b).into_owned());
    let m = robosim_cspm::Module::check_with_includes(&text, &names, &load);
    for d in m.diagnostics() {
        let line = text[..usize::from(d.range.start())].lines().count();
        println!("{line}: {d}");
    }
    let limits = robosim_cspm::Limits {
        max_stack: 1000 << 20,
        max_depth: 1_000_000,
        max_states: std::env::var("MAX_STATES").ok().and_then(|s| s.parse().ok()).unwrap_or(500_000),
        time: std::time::Duration::from_secs(120),
        ..robosim_cspm::Limits::default()
    };
    let mut ev = robosim_cspm::Evaluator::new(&m, &names, limits);
    for n in m.defined_names() {
        if n.starts_with("test") {
            match ev.value(&n) {
                Ok(v) => println!("{n} = {v}"),
                Err(e) => println!("{n}: {e}"),
            }
        }
    }
    for p in args {
        let t = std::time::Instant::now();
        let r = ev.eval_text(&p).and_then(|v| ev.lts_of(&v));
        eprintln!("{p}: {:?}", t.elapsed());
        match r {
            Ok(l) => {
                // States with no transition that ✓ does not lead to: deadlocks.
                let after_tick: std::collections::BTreeSet<u32> = l
                    .transitions
                    .iter()
                    .flatten()
                    .filter(|(lab, _)| *lab == robosim_cspm::Label::Tick)
                    .map(|(_, t)| *t)
                    .collect();
                let dead = (0..l.states() as u32)
                    .filter(|s| l.transitions[*s as usize].is_empty() && !after_tick.contains(s))
                    .count();
                println!("{p}: {} states, {dead} deadlocked", l.states());
            }
            Err(e) => println!("{p}: {e}"),
        }
    }
}
