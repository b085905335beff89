//! Generated models of any size, shared by the benchmarks, the profiling
//! examples and the incremental-vs-fresh tests.

/// A synthetic RoboChart model of about `lines` lines, in the style of real
/// models: machines with declarations, states with actions, transitions with
/// triggers, resets, deadlines, guards and actions. Names and numbers vary
/// from machine to machine, as in real models, so that no two machines share
/// subtrees.
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

/// A synthetic RoboSim model of `copies` copies of a small module (two
/// interfaces, a machine with inputs, outputs, a clock and a cycle, a
/// controller and a module), each with its own names, 97 lines per copy
/// (120 copies: 11,641 lines). Copy `k`'s guard
/// `condition not $obstacle` (in transition `t3`) is the one benchmarks
/// toggle to `not obstacle`, an RS:SM6 violation.
pub fn generated_robosim(copies: usize) -> String {
    let mut s = String::from("package bench_sim\n");
    for k in 0..copies {
        s.push_str(&format!(
            "
interface MovementI{k} {{
	move(lv : real, av : real)
	stop()
}}

interface ObstacleI{k} {{
	event obstacle
}}

stm SimSMovement{k} {{
	cycleDef cycle == 1
	const PI : real, lv : real, av : real
	var turns : nat = 0, last : real = 0
	clock MBC
	input context {{ uses ObstacleI{k} }}
	output context {{ requires MovementI{k} }}

	initial i0
	state SMoving {{
		entry $move(lv, 0)
	}}
	state DMoving {{ }}
	junction j0
	state STurning {{
		entry $move(0, av); turns = turns + 1
	}}
	state DTurning {{ }}
	junction j1
	junction j2

	transition t0 {{ from i0 to SMoving }}
	transition t1 {{ from SMoving to DMoving }}
	transition t2 {{
		from DMoving
		to j0
		exec
	}}
	transition t3 {{
		from j0
		to DMoving
		condition not $obstacle
	}}
	transition t4 {{
		from j0
		to j2
		#MBC
		condition $obstacle
		action $stop()
	}}
	transition t9 {{
		from j2
		to STurning
		condition turns < {k} + 10
		action last = lv
	}}
	transition t10 {{
		from j2
		to STurning
		condition turns >= {k} + 10
		action turns = 0
	}}
	transition t5 {{ from STurning to DTurning }}
	transition t6 {{
		from DTurning
		to j1
		exec
	}}
	transition t7 {{
		from j1
		to DTurning
		condition since(MBC) < PI / av
	}}
	transition t8 {{
		from j1
		to SMoving
		condition since(MBC) >= PI / av
	}}
}}

controller SimMovement{k} {{
	cycleDef cycle == 1
	uses ObstacleI{k}
	requires MovementI{k}
	sref sm = SimSMovement{k}
	connection SimMovement{k} on obstacle to sm on obstacle
}}

module SimCFootBot{k} {{
	cycleDef cycle == 1
	robotic platform FootBot{k} {{
		provides MovementI{k}
		uses ObstacleI{k}
	}}
	cref mv = SimMovement{k}
	connection FootBot{k} on obstacle to mv on obstacle ( _async )
}}
"
        ));
    }
    s
}
