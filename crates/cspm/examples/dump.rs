//! Prints a CSPm file's diagnostics, the values of its `test*` names and
//! the sizes of the LTSs of the processes named on the command line.
fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("a .csp file");
    let bytes = std::fs::read(path).expect("readable");
    let text = String::from_utf8_lossy(&bytes);
    let names = robosim_cspm::NoNames;
    let m = robosim_cspm::Module::check(&text, &names);
    for d in m.diagnostics() {
        let line = text[..usize::from(d.range.start())].lines().count();
        println!("{line}: {d}");
    }
    let mut ev = robosim_cspm::Evaluator::new(&m, &names, robosim_cspm::Limits::default());
    for n in m.defined_names() {
        if n.starts_with("test") {
            match ev.value(&n) {
                Ok(v) => println!("{n} = {v}"),
                Err(e) => println!("{n}: {e}"),
            }
        }
    }
    for p in args {
        match ev.lts(&p) {
            Ok(l) => println!("{p}: {} states, {:?}", l.states(), l.transitions.iter().take(8).collect::<Vec<_>>()),
            Err(e) => println!("{p}: {e}"),
        }
    }
}
