//! The generated benchmark input, shared by the benchmark and the
//! `parse_file` profiling example.

/// A synthetic RoboChart model of about `lines` lines, in the style of real
/// models: machines with declarations, states with actions, transitions with
/// triggers, resets, deadlines, guards and actions. Names and numbers vary
/// from machine to machine, as in real models, so that no two machines share
/// subtrees.
#[allow(dead_code)]
pub fn generated_model(lines: usize) -> String {
    let mut s = String::from(
        "package bench\nimport core::*\ninterface Ops { move(lv : real, av : real) stop() }\ninterface Evs { event obstacle event reading : nat }\n",
    );
    let mut i = 0;
    while s.lines().count() < lines {
        s.push_str(&format!(
            "\nstm Machine{i} {{\n\trequires Ops\n\tuses Evs\n\tvar count{i} : nat = {i}, speed{i} : real\n\tconst LIMIT{i} : real = {i}.5\n\tclock C{i}\n\tinitial i{i}\n\tjunction j{i}\n"
        ));
        for k in 0..8 {
            let n = i * 8 + k;
            s.push_str(&format!(
                "\tstate S{n} {{\n\t\tentry move({k}.0, {n}); count{i} = count{i} + {k}\n\t\texit stop()\n\t}}\n\ttransition t{n} {{\n\t\tfrom S{n}\n\t\tto j{i}\n\t\ttrigger reading?count{i}\n\t\t#C{i}\n\t\t<{{ {k} }}\n\t\tcondition count{i} > {n} /\\ since(C{i}) >= LIMIT{i} / {k}\n\t\taction speed{i} = speed{i} * {n}.25; move(speed{i}, -{k})\n\t}}\n"
            ));
        }
        s.push_str(&format!(
            "\ttransition ti{i} {{\n\t\tfrom i{i}\n\t\tto S{}\n\t}}\n\ttransition tj{i} {{\n\t\tfrom j{i}\n\t\tto S{}\n\t\tcondition else\n\t}}\n}}\n",
            i * 8,
            i * 8 + 1
        ));
        i += 1;
    }
    s
}
