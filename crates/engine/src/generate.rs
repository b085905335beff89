//! Scalable models written as text, for benchmarks and tests of the
//! engine on state spaces of a chosen size.

/// A RoboChart module `Mod` of `n` machines with `k` states each: machine
/// `Mi` calls its platform operation `opi()` on entering each state, waits
/// a time unit, and moves to its next state on its own input `ei`. Its
/// constrained design has about (2k)^n states.
pub fn design(n: usize, k: usize) -> String {
    let mut s = String::from("interface I {\n");
    for i in 0..n {
        s.push_str(&format!("    event e{i}\n    op{i}()\n"));
    }
    s.push_str("}\n");
    for i in 0..n {
        s.push_str(&format!("stm M{i} {{\n    uses I requires I\n    initial i0\n"));
        for j in 0..k {
            s.push_str(&format!("    state S{j} {{ entry op{i}(); wait(1) }}\n"));
        }
        s.push_str("    transition t { from i0 to S0 }\n");
        for j in 0..k {
            s.push_str(&format!("    transition t{j} {{ from S{j} to S{} trigger e{i} }}\n", (j + 1) % k));
        }
        s.push_str("}\n");
    }
    s.push_str("controller C {\n    uses I requires I\n");
    for i in 0..n {
        s.push_str(&format!("    sref m{i} = M{i}\n    connection C on e{i} to m{i} on e{i}\n"));
    }
    s.push_str("}\nmodule Mod {\n    robotic platform P { uses I provides I }\n    cref c = C\n");
    for i in 0..n {
        s.push_str(&format!("    connection P on e{i} to c on e{i}\n"));
    }
    s.push_str("}\n");
    s
}

/// The RoboSim simulation of [`design`] (module `Mod`, period 1): each
/// machine takes its decision in the cycle after the one that entered the
/// state, as the paper's Figure 3 does. It is sound.
pub fn simulation(n: usize, k: usize) -> String {
    let mut s = String::from("interface I {\n");
    for i in 0..n {
        s.push_str(&format!("    event e{i}\n    op{i}()\n"));
    }
    s.push_str("}\n");
    for i in 0..n {
        s.push_str(&format!(
            "stm M{i} {{\n    cycleDef cycle == 1\n    input context {{ uses I }}\n    output context {{ requires I }}\n    initial i0\n"
        ));
        for j in 0..k {
            s.push_str(&format!("    state S{j} {{ entry $op{i}() }}\n    state D{j} {{ }}\n    junction J{j}\n"));
            s.push_str(&format!(
                "    transition s{j} {{ from S{j} to D{j} }}\n    transition x{j} {{ from D{j} to J{j} exec }}\n"
            ));
            s.push_str(&format!("    transition y{j} {{ from J{j} to S{} condition $e{i} }}\n", (j + 1) % k));
            s.push_str(&format!("    transition z{j} {{ from J{j} to D{j} condition not $e{i} }}\n"));
        }
        s.push_str("    transition t { from i0 to S0 }\n}\n");
    }
    s.push_str("controller C {\n    cycleDef cycle == 1\n    uses I requires I\n");
    for i in 0..n {
        s.push_str(&format!("    sref m{i} = M{i}\n    connection C on e{i} to m{i} on e{i}\n"));
    }
    s.push_str(
        "}\nmodule Mod {\n    cycleDef cycle == 1\n    robotic platform P { uses I provides I }\n    cref c = C\n",
    );
    for i in 0..n {
        s.push_str(&format!("    connection P on e{i} to c on e{i}\n"));
    }
    s.push_str("}\n");
    s
}
