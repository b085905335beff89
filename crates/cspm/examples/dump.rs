fn main() {
    let path = std::env::args().nth(1).unwrap();
    let text = std::fs::read_to_string(path).unwrap();
    let p = robosim_cspm::parse(&text);
    if std::env::args().nth(2).is_some() {
        print!("{}", p.debug_dump());
    } else {
        for e in p.errors() {
            let line = text[..usize::from(e.range.start())].lines().count();
            println!("{line}: {e}");
        }
    }
}
