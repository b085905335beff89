//! Counterexamples and notes in the user's terms: each step of a path
//! described (which machine did what, where in the source), the
//! specification's side of a refinement, the stuck point of a deadlock,
//! the notes on domains and defaults, and the text renderings the CLI and
//! the editor show.

use super::*;

/// `{a, b}` with the events' names.
pub(super) fn event_set<L: Lts>(lts: &L, events: &[Event]) -> String {
    format!("{{{}}}", events.iter().map(|e| lts.event_name(*e)).collect::<Vec<_>>().join(", "))
}

pub(super) fn describe_cex<L: Lts, S: Lts, X>(imp: &L, spec: &S, cex: &RefinementCex<X>) -> String {
    let _ = spec;
    match cex {
        RefinementCex::Trace { event, .. } => {
            format!("the implementation can perform {} where the specification cannot", imp.event_name(event.event))
        }
        RefinementCex::Refusal { acceptances, .. } => {
            let sets: Vec<String> = acceptances.iter().map(|acc| event_set(imp, acc)).collect();
            format!("the implementation refuses every event the specification must offer: one of {}", sets.join(" or "))
        }
        RefinementCex::TockRefusal { offered, acceptances, .. } => {
            let offered: Vec<Event> = offered.iter().copied().filter(|&e| e != TOCK).collect();
            let then = if acceptances.is_empty() {
                "the specification cannot let time pass after the same trace".to_string()
            } else {
                let sets: Vec<String> = acceptances
                    .iter()
                    .map(|acc| event_set(imp, &acc.iter().copied().filter(|&e| e != TOCK).collect::<Vec<_>>()))
                    .collect();
                format!(
                    "the specification lets time pass after the same trace only while offering {}",
                    sets.join(" or ")
                )
            };
            format!(
                "the implementation lets time pass while offering only {} (tick-tock model); {then}",
                event_set(imp, &offered)
            )
        }
        RefinementCex::Divergence { .. } => "the implementation can compute forever without finishing its cycle".into(),
    }
}

pub(super) fn refinement_counterexample<S: Lts>(
    imp: &Side<'_>,
    spec: &S,
    design: &Design,
    cex: &RefinementCex<Packed>,
) -> Counterexample {
    let (kind, path) = match cex {
        RefinementCex::Trace { path, .. } => ("trace", path),
        RefinementCex::Refusal { path, .. } => ("refusal", path),
        RefinementCex::TockRefusal { path, .. } => ("tock-refusal", path),
        RefinementCex::Divergence { path, .. } => ("divergence", path),
    };
    let steps = sim_steps(imp, design, &values_path(path, |p| imp.values(p)));
    let mut explanation = vec![describe_cex(imp, spec, cex)];
    explanation.extend(saturation_note(&steps));
    Counterexample { kind, steps, explanation, stuck_at: Vec::new(), specification: Vec::new() }
}

/// What the specification does on the counterexample's visible trace (up
/// to the offending event): the shortest run of `spec` with that trace,
/// found breadth first within a small budget, as located steps.
pub(super) fn specification_steps(
    spec: &Side<'_>,
    design: &Design,
    cex: &RefinementCex<Packed>,
    budget: &Budget,
) -> Vec<Step> {
    let (path, drop_last) = match cex {
        // The offending step (an event, or the `tock` refused too much
        // before) is not the specification's.
        RefinementCex::Trace { path, .. } | RefinementCex::TockRefusal { path, .. } => (path, true),
        RefinementCex::Refusal { path, .. } | RefinementCex::Divergence { path, .. } => (path, false),
    };
    let mut trace: Vec<crate::lts::Event> = path.steps.iter().map(|(l, _)| l.event).filter(|&e| e != TAU).collect();
    if drop_last {
        trace.pop();
    }
    let limit = budget.max_states.min(200_000) as usize;
    let start = spec.initial();
    // (state, events of the trace done) → how it was reached.
    type Node = (Packed, usize);
    let mut parent: std::collections::HashMap<Node, Option<(Node, Label)>> = std::collections::HashMap::new();
    parent.insert((start.clone(), 0), None);
    let mut queue = std::collections::VecDeque::from([(start, 0usize)]);
    let mut found = None;
    let mut succ = Vec::new();
    while let Some((st, k)) = queue.pop_front() {
        if k == trace.len() {
            found = Some((st, k));
            break;
        }
        if parent.len() > limit {
            return Vec::new();
        }
        succ.clear();
        spec.successors(&st, &mut succ);
        for (label, next) in succ.drain(..) {
            let k2 = if label.event == TAU {
                k
            } else if label.event == trace[k] {
                k + 1
            } else {
                continue;
            };
            let key = (next, k2);
            if !parent.contains_key(&key) {
                parent.insert(key.clone(), Some(((st.clone(), k), label)));
                queue.push_back(key);
            }
        }
    }
    let Some(mut at) = found else { return Vec::new() };
    let mut steps = Vec::new();
    while let Some(Some((prev, label))) = parent.get(&at) {
        steps.push((*label, at.0.clone()));
        at = prev.clone();
    }
    steps.reverse();
    let packed = Path { initial: at.0, steps };
    sim_steps(spec, design, &values_path(&packed, |p| spec.values(p)))
}

/// The steps of a path of any LTS over a design's state vector.
/// A path of packed states as state vectors.
pub(super) fn values_path(path: &Path<Packed>, values: impl Fn(&Packed) -> State) -> Path<State> {
    Path { initial: values(&path.initial), steps: path.steps.iter().map(|(l, s)| (*l, values(s))).collect() }
}

pub(super) fn sim_steps<L: Lts>(lts: &L, design: &Design, path: &Path<State>) -> Vec<Step> {
    let mut steps = Vec::new();
    let mut prev: &State = &path.initial;
    let (mut cycle, mut time, mut after_tock) = (0u32, 0u32, false);
    for (label, next) in &path.steps {
        let name = label.shown(|e| lts.event_name(e), |n| lts.event_name(n));
        if name.starts_with("registerRead") && after_tock {
            cycle += 1;
            after_tock = false;
        }
        let (description, location) = describe_move(design, prev, next, label);
        steps.push(Step { event: name, visible: label.event != TAU, cycle, time, description, location });
        if label.event == TOCK {
            time += 1;
            after_tock = true;
        }
        prev = next;
    }
    steps
}

/// The reason with its place as `file:line:column` (1-based, columns in
/// characters as editors count them).
pub(super) fn unsupported_reason(db: &dyn Db, ws: Workspace, u: &Unsupported) -> String {
    let Some((path, range)) = &u.location else {
        return u.message.clone();
    };
    let Some(file) = ws.files(db).iter().find(|f| f.path(db) == path) else {
        return format!("{} ({path})", u.message);
    };
    let text = file.text(db);
    let index = robosim_syntax::line_index::LineIndex::new(text);
    let at = index.line_col(text, range.start());
    format!("{} ({path}:{}:{})", u.message, at.line + 1, at.col + 1)
}

pub(crate) fn domains_note(design: &Design) -> String {
    let doms: Vec<String> = design.domains.iter().map(|(n, d)| format!("{n} = {{{}..{}}}", d.lo, d.hi)).collect();
    let mut s = format!("domains: {}", doms.join(", "));
    if !design.constants.is_empty() {
        let cs: Vec<String> = design.constants.iter().map(|(n, _, shown)| format!("{n} = {shown}")).collect();
        s.push_str(&format!("; constants: {}", cs.join(", ")));
    }
    if let Some(b) = design.channels.iter().find_map(|c| c.buffer) {
        s.push_str(&format!("; {}", b.policy.describe()));
    }
    if !design.defaults.is_empty() {
        s.push_str(&format!("; RoboTool's defaults, as the model gives no value: {}", design.defaults.join(", ")));
    }
    for r in &design.readings {
        s.push_str(&format!("; {r}"));
    }
    s
}

/// The steps of a path, with the design's moves identified and located.
pub(super) fn path_steps(lts: &Constrained<'_>, design: &Design, path: &Path<State>) -> Vec<Step> {
    sim_steps(lts, design, path)
}

/// Which machine moved between `prev` and `next`, and what it did.
pub(crate) fn describe_move(
    design: &Design,
    prev: &[i32],
    next: &[i32],
    _label: &Label,
) -> (Option<String>, Option<Location>) {
    for m in &design.machines {
        // The machine's control slots (leaf, pc, wait, transition, deadline,
        // and its activities' and timers'): two transitions can lead to the
        // same leaf and pc (exec ones do).
        let ctl = |st: &[i32]| m.control(st);
        if ctl(prev) == ctl(next) {
            continue;
        }
        let mut moves = Vec::new();
        if m.moves(prev, &mut moves).is_err() {
            continue;
        }
        // The move whose effect matches (a tock, or a settle after it, is not in `moves`).
        for mv in &moves {
            let mut trial = prev.to_vec();
            let mut saturated = false;
            if m.apply_noting(&mut trial, &design.clocks, mv.act, received(m, mv.act, prev), &mut saturated).is_err() {
                continue;
            }
            if ctl(&trial) != ctl(next) {
                continue;
            }
            let (what, at) = describe_act(design, m, mv.act, prev, next);
            let what = what.map(|w| if saturated { format!("{w} {SATURATED}") } else { w });
            return (what, at);
        }
        return (Some(format!("{}: now {}", m.name, m.describe(next))), None);
    }
    (None, None)
}

/// A value `act` could receive in `prev`, for replaying it: a value
/// received goes to a variable (or, [`crate::ir::Machine::deferred`], to
/// the thread's pending write), which no control slot holds, so any value
/// of the variable's type replays the step's control.
fn received(m: &crate::ir::Machine, act: Act, prev: &[i32]) -> Option<crate::ir::Val> {
    let bind = match act {
        Act::Fire(t) => match &m.transitions[t as usize].trigger {
            Some(crate::ir::Trigger::In { bind, .. }) => *bind,
            _ => None,
        },
        Act::Comm | Act::ActivityComm(_) => {
            let pc = match act {
                Act::ActivityComm(k) => prev[m.activities[k as usize].pc_slot as usize],
                _ => m.pc(prev) as i32,
            };
            match m.code.get(pc as usize) {
                Some(Instr::In { bind, .. }) => *bind,
                _ => None,
            }
        }
        _ => None,
    };
    bind.map(|(_, dom)| dom.lo)
}

/// Marks a step whose arithmetic saturated.
pub(super) const SATURATED: &str = "(arithmetic saturated)";

/// The note added to a counterexample that depends on saturation.
pub(super) fn saturation_note(steps: &[Step]) -> Option<String> {
    let step = steps.iter().position(|s| s.description.as_deref().is_some_and(|d| d.ends_with(SATURATED)))?;
    Some(format!(
        "note: at step {} a result left its type and RoboTool's sticky arithmetic kept the left operand; \
         the verdict depends on the bounds of the types (widen them with `nametype core_X = {{a..b}}`)",
        step + 1
    ))
}

/// Where the instruction at `pc` of machine `m` is in the model.
pub(super) fn code_location(design: &Design, m: &crate::ir::Machine, pc: usize) -> Option<Location> {
    let range = *m.code_ranges.get(pc)?;
    let file = m.code_files.get(pc).and_then(|&f| design.files.get(f as usize)).cloned().unwrap_or_default();
    Some(Location { file, range })
}

/// What machine `m` did by `act`, and where in the model.
pub(super) fn describe_act(
    design: &Design,
    m: &crate::ir::Machine,
    act: Act,
    prev: &[i32],
    next: &[i32],
) -> (Option<String>, Option<Location>) {
    let at = |n: Option<u16>| n.map(|n| m.nodes[n as usize].name.clone()).unwrap_or_else(|| "-".into());
    let pc = m.pc(prev) as usize;
    let here = code_location(design, m, pc);
    match act {
        Act::Fire(t) | Act::Junction(t) => {
            let tr = &m.transitions[t as usize];
            let what = format!(
                "{}: takes {} ({} → {})",
                m.name, tr.name, m.nodes[tr.source as usize].name, m.nodes[tr.target as usize].name,
            );
            let file = design.files.get(tr.file as usize).cloned().unwrap_or_default();
            (Some(what), Some(Location { file, range: tr.range }))
        }
        Act::Comm => {
            let what = out_verb(design, &m.code[pc]).unwrap_or("receives");
            // Between states (on a transition out of a junction) there is
            // no state to name.
            let place = m.leaf(prev).map(|l| format!(" in {}", at(Some(l)))).unwrap_or_default();
            (Some(format!("{}: {what}{place}", m.name)), here)
        }
        Act::Choose(n) => (Some(format!("{}: the wait interval resolves to {n}", m.name)), here),
        Act::Exec if m.pending.first().is_some_and(|p| prev[p.flag as usize] != 0) => {
            (Some(format!("{}: writes the value it received, now {}", m.name, m.describe(next))), here)
        }
        Act::Exec if assignment_read(m, pc, prev).is_some() => {
            let what = assignment_step(m, pc, prev);
            (Some(format!("{}: {what}, now {}", m.name, m.describe(next))), here)
        }
        Act::Exec if matches!(m.code.get(pc), Some(Instr::Wait)) => {
            (Some(format!("{}: goes on after its wait, now {}", m.name, m.describe(next))), here)
        }
        Act::Exec if matches!(m.code.get(pc), Some(Instr::Assign { shared: true, .. })) => {
            (Some(format!("{}: writes a shared variable, now {}", m.name, m.describe(next))), here)
        }
        Act::Exec if matches!(m.latches.get(pc), Some(Some(_))) => {
            (Some(format!("{}: reads the values its communication carries, now {}", m.name, m.describe(next))), here)
        }
        Act::Exec if m.volatile.get(pc) == Some(&true) => {
            (Some(format!("{}: reads what another thread writes, now {}", m.name, m.describe(next))), here)
        }
        Act::Exec if m.paused_durings.get(pc) == Some(&true) => {
            (Some(format!("{}: starts the during action of {}", m.name, at(m.leaf(prev)))), here)
        }
        // Stopped after a communication (RT-16/18): the rest of the action.
        Act::Exec => (Some(format!("{}: goes on after its communication, now {}", m.name, m.describe(next))), here),
        Act::ActivityComm(k) | Act::ActivityChoose(k, _) | Act::ActivityExec(k) => {
            let a = &m.activities[k as usize];
            let pc = prev[a.pc_slot as usize] as usize;
            let here = code_location(design, m, pc);
            let write = matches!(m.code.get(pc), Some(Instr::Assign { .. }));
            if matches!(act, Act::ActivityExec(_)) && !write && m.paused_durings.get(pc) == Some(&true) {
                return (Some(format!("{}: starts the during action of {}", m.name, at(Some(a.state)))), here);
            }
            let pending = m.pending.get(k as usize + 1).is_some_and(|p| prev[p.flag as usize] != 0);
            let what = match (act, m.code.get(pc)) {
                (Act::ActivityExec(_), _) if pending => "writes the value it received".into(),
                (Act::ActivityExec(_), _) if assignment_read(m, pc, prev).is_some() => {
                    assignment_step(m, pc, prev).into()
                }
                (Act::ActivityExec(_), _) if matches!(m.latches.get(pc), Some(Some(_))) => {
                    "reads the values its communication carries".into()
                }
                (Act::ActivityChoose(_, n), _) => format!("the wait interval resolves to {n}"),
                (_, Some(i @ Instr::Out { .. })) => out_verb(design, i).unwrap_or_default().into(),
                (_, Some(Instr::In { .. })) => "receives".into(),
                (_, Some(Instr::Wait)) => "goes on after its wait".into(),
                (_, Some(Instr::Assign { .. })) => "writes a variable".into(),
                _ => "goes on after its communication".into(),
            };
            (Some(format!("{}: {what} in the during action of {}", m.name, at(Some(a.state)))), here)
        }
    }
}

/// At an assignment whose read and write are hidden steps of their own
/// (`reads.rs`): whether it has read its value.
fn assignment_read(m: &crate::ir::Machine, pc: usize, st: &[i32]) -> Option<bool> {
    match (m.code.get(pc), m.latches.get(pc)) {
        (Some(Instr::Assign { .. }), Some(Some(l))) => Some(st[l.flag as usize] != 0),
        _ => None,
    }
}

/// The step an assignment of [`assignment_read`] takes, in words.
fn assignment_step(m: &crate::ir::Machine, pc: usize, st: &[i32]) -> &'static str {
    if assignment_read(m, pc, st) == Some(true) {
        "writes the value it read"
    } else {
        "reads the value it assigns"
    }
}

/// What a machine does at an output instruction, in words (none for other
/// instructions).
pub(super) fn out_verb(design: &Design, instr: &Instr) -> Option<&'static str> {
    match instr {
        Instr::Out { store: Some(_), .. } => Some("updates the platform variable"),
        // A RoboSim output event (`$e!v`) is urgent too, but no call.
        Instr::Out { chan, urgent: true, .. } if design.channels.get(*chan as usize).is_some_and(|c| !c.is_call) => {
            Some("outputs")
        }
        // RT-11: in a RoboSim operation on its own, a call of another
        // operation (not an output) is a call event of its own (`opCall`).
        // RT-19: so is a RoboSim machine's call of one nothing defines.
        Instr::Out { chan, urgent: true, .. }
            if design
                .channels
                .get(*chan as usize)
                .is_some_and(|c| c.soft_call || (design.level == crate::ir::Level::Operation && !c.register_write)) =>
        {
            Some("calls the operation")
        }
        Instr::Out { urgent: true, .. } => Some("calls the platform operation"),
        Instr::Out { .. } => Some("outputs"),
        _ => None,
    }
}

pub(super) fn deadlock_counterexample(lts: &Constrained<'_>, design: &Design, path: &Path<Packed>) -> Counterexample {
    let path = &values_path(path, |p| lts.values(p));
    let steps = path_steps(lts, design, path);
    let last: &State = path.steps.last().map(|(_, s)| s).unwrap_or(&path.initial);
    let mut explanation = Vec::new();
    let mut stuck_at = Vec::new();
    let time = steps.iter().filter(|s| s.event == "tock").count();
    let written = lts.written(last);
    let phase = lts.phase(last);
    for (mname, mv) in lts.design_moves(last) {
        let Some(m) = design.machines.iter().find(|m| m.name == mname) else { continue };
        let pc = m.pc(last) as usize;
        if let Offer::Out { chan, args } = &mv.offer {
            let c = &design.channels[*chan as usize];
            let values = args.iter().map(|a| a.to_string()).collect::<Vec<_>>().join(", ");
            let urgent = matches!(m.code.get(pc), Some(Instr::Out { urgent: true, .. }));
            let mut line = if c.var {
                format!(
                    "{mname} ({}) must set {} = {values} now (updates of platform variables cannot be delayed)",
                    m.describe(last),
                    c.name
                )
            } else {
                let call = format!("{}({values})", c.name);
                format!("{mname} ({}) must {} {call} now", m.describe(last), if urgent { "call" } else { "output" })
            };
            if urgent && !c.var {
                line.push_str(" (platform operation calls cannot be delayed)");
            }
            if written.contains(&c.name) {
                line.push_str(&format!(
                    ", but `{}` was already written in this cycle (one write per output per cycle)",
                    c.name
                ));
            } else {
                line.push_str(&format!(", but the cycle assumption forbids it: the simulation is {phase}"));
            }
            explanation.push(line);
            stuck_at.extend(code_location(design, m, pc));
        }
    }
    if explanation.is_empty() {
        explanation.push(format!(
            "at t = {time} nothing can happen: the design {}; the simulation is {phase}",
            design
                .machines
                .iter()
                .map(|m| format!("{} is {}", m.name, m.describe(last)))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    explanation.extend(saturation_note(&steps));
    Counterexample { kind: "deadlock", steps, explanation, stuck_at, specification: Vec::new() }
}

/// A counterexample grouped by cycle, one line per step: reads, the
/// design's steps with their description and source (`locate` prints a
/// location), writes, time passing; then why nothing more can happen.
/// The command line and the editor's hover both show this table.
pub fn counterexample_table(c: &Counterexample, locate: &dyn Fn(&Location) -> String) -> String {
    let mut lines: Vec<String> = Vec::new();
    let mut cycle = u32::MAX;
    let mut tocks = 0;
    let flush = |lines: &mut Vec<String>, tocks: &mut u32| {
        if *tocks > 0 {
            let unit = if *tocks == 1 { "time unit passes" } else { "time units pass" };
            lines.push(format!("           {tocks} {unit}"));
            *tocks = 0;
        }
    };
    for step in &c.steps {
        if step.event == "tock" {
            tocks += 1;
            continue;
        }
        flush(&mut lines, &mut tocks);
        let (what, event) = if let Some(e) = step.event.strip_prefix("registerRead.") {
            ("read  ", e)
        } else if let Some(e) = step.event.strip_prefix("registerWrite.") {
            ("write ", e)
        } else if step.visible {
            ("event ", step.event.as_str())
        } else {
            ("design", step.event.as_str())
        };
        if !step.visible && step.description.is_none() && event == "τ" {
            continue;
        }
        if step.cycle != cycle {
            cycle = step.cycle;
            lines.push(format!("cycle {cycle}  t = {}", step.time));
        }
        let mut line = format!("  {what} {event}");
        if let Some(d) = &step.description {
            line.push_str(&format!("  {d}"));
        }
        if let Some(l) = &step.location {
            line.push_str(&format!("  --> {}", locate(l)));
        }
        lines.push(line);
    }
    flush(&mut lines, &mut tocks);
    lines.extend(c.explanation.iter().map(|e| format!("stuck: {e}")));
    lines.extend(c.stuck_at.iter().map(|l| format!("  --> {}", locate(l))));
    if !c.specification.is_empty() {
        lines.push("the specification, on the same trace:".into());
        let design_only: Vec<&Step> =
            c.specification.iter().filter(|s| !s.visible && s.description.is_some()).collect();
        for step in design_only {
            let mut line = format!("  design {}", step.event);
            if let Some(d) = &step.description {
                line.push_str(&format!("  {d}"));
            }
            if let Some(l) = &step.location {
                line.push_str(&format!("  --> {}", locate(l)));
            }
            lines.push(line);
        }
    }
    let mut s = lines.join("\n");
    s.push('\n');
    s
}

/// The LTS's events of a step, for tests: visible names, hidden ones in
/// parentheses, τ left out.
pub fn trace_text(steps: &[Step]) -> String {
    steps.iter().filter(|s| s.event != "τ").map(|s| s.event.clone()).collect::<Vec<_>>().join(" ")
}
