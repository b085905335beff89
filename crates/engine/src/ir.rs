//! The compiled form of RoboChart machines: bounded data, expressions over
//! slots of a flat state vector, and statements as a small instruction list
//! per machine. Built by [`crate::lower`], executed by [`crate::machine`].

use robosim_syntax::TextRange;

/// A value: every type the engine supports is a bounded integer range
/// (booleans are `0..=1`, enumerations `0..n`, reals are integers as in
/// RoboTool).
pub type Val = i64;

/// A bounded domain `lo..=hi`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Dom {
    /// Least value.
    pub lo: Val,
    /// Greatest value.
    pub hi: Val,
}

impl Dom {
    /// Booleans.
    pub const BOOL: Dom = Dom { lo: 0, hi: 1 };

    /// Whether `v` is in the domain.
    pub fn contains(self, v: Val) -> bool {
        self.lo <= v && v <= self.hi
    }

    /// The number of values.
    pub fn size(self) -> u64 {
        (self.hi - self.lo + 1).max(0) as u64
    }
}

/// Arithmetic operators, sticky on overflow as RoboTool's `Plus`, `Minus`…
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum ArOp {
    Add,
    Sub,
    Mul,
    Div,
    Mod,
}

/// Comparison operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum CmpOp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

/// Logical connectives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum LogOp {
    And,
    Or,
    Implies,
    Iff,
}

/// An expression over the state vector.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    /// A literal or a constant's value.
    Const(Val),
    /// The variable in this slot.
    Slot(u16),
    /// The clock in this slot (`since(C)`, `sinceEntry(S)`).
    Clock(u16),
    /// `-e`, sticky in the domain.
    Neg(Box<Expr>, Dom),
    /// `not e`.
    Not(Box<Expr>),
    /// `a op b`, sticky in the domain: the left operand when the result
    /// falls outside it.
    Arith(ArOp, Box<Expr>, Box<Expr>, Dom),
    /// `a op b` on numbers.
    Cmp(CmpOp, Box<Expr>, Box<Expr>),
    /// `a op b` on booleans.
    Log(LogOp, Box<Expr>, Box<Expr>),
    /// `if c then a else b end`.
    If(Box<Expr>, Box<Expr>, Box<Expr>),
    /// A tuple `(| a, b |)` encoded in one value: the components (each with
    /// its domain) in mixed radix, the first the most significant, so that
    /// the encodings count the tuples in CSPm's order of `e.a.b`.
    Tuple(Vec<(Expr, Dom)>),
    /// `t[i]` of an encoded tuple: `(t / stride) % size + lo`.
    Proj(Box<Expr>, Val, Dom),
    /// The set `{e}` of a finite set type, as a bitmask: bit `e - lo`.
    Elem(Box<Expr>, Dom),
    /// An operation on bitmask sets.
    Set(SetOp, Box<Expr>, Box<Expr>),
    /// `size(s)`: the number of elements of a bitmask set.
    Card(Box<Expr>),
    /// A value sent on a channel: it must be one of the channel's type
    /// (FDR stops with an error otherwise, [`EvalError::OutOfDomain`]).
    Checked(Box<Expr>, Dom),
    /// An operation on bounded sequences, each encoded in one value (see
    /// [`SeqDom`]).
    Seq(SeqOp, Vec<Expr>, SeqDom),
}

/// Operations on bounded sequences (the operands of [`Expr::Seq`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeqOp {
    /// `<a, b, …>`: the operands are the elements.
    Lit,
    /// `s ^ t`, `concat(s, t)`.
    Cat,
    /// `head(s)`: an element (an error on `<>`, as in CSPm).
    Head,
    /// `tail(s)` (an error on `<>`, as in CSPm).
    Tail,
    /// `last(s)`: an element (an error on `<>`).
    Last,
    /// `front(s)`: all but the last (an error on `<>`).
    Front,
    /// `reverse(s)`.
    Reverse,
    /// `#s`, `size(s)`: a number.
    Len,
    /// `filter(s, A)`: the elements of `s` in the bitmask set `A`, in order.
    Filter,
}

/// A sequence type: elements of `el`, at most `max` of them. A sequence is
/// encoded in one value: the number of shorter sequences plus its elements
/// in base `|el|` (the first the most significant), so that the codes are
/// dense (`0` is `<>`) and every code is a sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SeqDom {
    /// The elements' domain.
    pub el: Dom,
    /// The longest sequence the encoding holds.
    pub max: u32,
}

impl SeqDom {
    /// The number of sequences of length `len` or less.
    fn below(self, len: u32) -> u64 {
        let n = self.el.size();
        (0..len).fold((0u64, 1u64), |(acc, p), _| (acc.saturating_add(p), p.saturating_mul(n))).0
    }

    /// The number of sequences of the type (codes `0..count`).
    pub fn count(self) -> u64 {
        self.below(self.max + 1)
    }

    /// The code of the sequence `items` (values of `el`).
    pub fn encode(self, items: &[Val]) -> Result<Val, EvalError> {
        if items.len() > self.max as usize {
            return Err(EvalError::SeqTooLong(self.max));
        }
        let n = self.el.size() as Val;
        let mut digits: Val = 0;
        for &v in items {
            if !self.el.contains(v) {
                return Err(EvalError::OutOfType);
            }
            digits = digits * n + (v - self.el.lo);
        }
        Ok(self.below(items.len() as u32) as Val + digits)
    }

    /// The elements of the sequence `code`.
    pub fn decode(self, code: Val) -> Vec<Val> {
        let n = self.el.size().max(1);
        let mut rest = code.max(0) as u64;
        let mut len = 0u32;
        let mut p = 1u64;
        while len < self.max && rest >= p {
            rest -= p;
            p = p.saturating_mul(n);
            len += 1;
        }
        let mut out = vec![self.el.lo; len as usize];
        for slot in out.iter_mut().rev() {
            *slot = self.el.lo + (rest % n) as Val;
            rest /= n;
        }
        out
    }

    fn eval(self, op: SeqOp, args: &[Expr], st: &[i32], saturated: &mut bool) -> Result<Val, EvalError> {
        let mut vals = Vec::with_capacity(args.len());
        for a in args {
            vals.push(a.eval(st, saturated)?);
        }
        let seq = |i: usize| self.decode(vals.get(i).copied().unwrap_or(0));
        Ok(match op {
            SeqOp::Lit => self.encode(&vals)?,
            SeqOp::Cat => {
                let mut s = seq(0);
                s.extend(seq(1));
                self.encode(&s)?
            }
            SeqOp::Head => *seq(0).first().ok_or(EvalError::EmptySeq("head"))?,
            SeqOp::Tail => {
                let s = seq(0);
                if s.is_empty() {
                    return Err(EvalError::EmptySeq("tail"));
                }
                self.encode(&s[1..])?
            }
            SeqOp::Last => *seq(0).last().ok_or(EvalError::EmptySeq("last"))?,
            SeqOp::Front => {
                let s = seq(0);
                if s.is_empty() {
                    return Err(EvalError::EmptySeq("front"));
                }
                self.encode(&s[..s.len() - 1])?
            }
            SeqOp::Reverse => {
                let mut s = seq(0);
                s.reverse();
                self.encode(&s)?
            }
            SeqOp::Len => seq(0).len() as Val,
            SeqOp::Filter => {
                let set = vals.get(1).copied().unwrap_or(0);
                let kept: Vec<Val> =
                    seq(0).into_iter().filter(|v| v - self.el.lo < 62 && set & (1 << (v - self.el.lo)) != 0).collect();
                self.encode(&kept)?
            }
        })
    }
}

/// Operations on finite sets encoded as bitmasks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SetOp {
    /// `union(a, b)`.
    Union,
    /// `inter(a, b)`.
    Inter,
    /// `diff(a, b)`.
    Diff,
    /// `subset(a, b)`: a boolean.
    Subset,
    /// `a` (a singleton, see [`Expr::Elem`]) meets `b`: `x in b`.
    Meets,
}

/// How the message of an [`EvalError::OutOfDomain`] starts (the verdict
/// turns it into FDR's error and its remedy).
pub const OUT_OF_DOMAIN: &str = "the value ";

/// Why an evaluation failed (reported, never a panic).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum EvalError {
    /// Modulus by zero (division by zero divides by one, RT-6), or a
    /// quotient out of range.
    DivByZero,
    /// A tuple component or set element outside its type (it has no
    /// encoding: the check cannot go on).
    OutOfType,
    /// A value sent or assigned outside the type of the channel or
    /// variable (the value, the type's values): RoboTool's CSPm communicates
    /// it on a channel of that type, and FDR stops with an error.
    OutOfDomain(Val, Dom),
    /// A sequence longer than its type's bound (the check cannot go on
    /// without a wrong verdict).
    SeqTooLong(u32),
    /// `head` or `tail` of the empty sequence (an error in CSPm too).
    EmptySeq(&'static str),
}

impl Expr {
    /// Evaluates over `st`. `saturated` is set when sticky arithmetic kept
    /// its left operand.
    pub fn eval(&self, st: &[i32], saturated: &mut bool) -> Result<Val, EvalError> {
        Ok(match self {
            Expr::Const(v) => *v,
            Expr::Slot(s) | Expr::Clock(s) => st[*s as usize] as Val,
            Expr::Neg(e, d) => {
                let v = e.eval(st, saturated)?;
                if d.contains(-v) {
                    -v
                } else {
                    *saturated = true;
                    v
                }
            }
            Expr::Not(e) => (e.eval(st, saturated)? == 0) as Val,
            Expr::Arith(op, a, b, d) => {
                let x = a.eval(st, saturated)?;
                let y = b.eval(st, saturated)?;
                let r = match op {
                    ArOp::Add => x + y,
                    ArOp::Sub => x - y,
                    ArOp::Mul => x.saturating_mul(y),
                    // CSPm division and modulus truncate towards zero.
                    // RoboTool wraps every divisor so that `x / 0` is
                    // `x / 1` (robotool-facts RT-6); the modulus is not
                    // wrapped, so `x % 0` stays an error.
                    ArOp::Div => x.checked_div(if y == 0 { 1 } else { y }).ok_or(EvalError::DivByZero)?,
                    ArOp::Mod => x.checked_rem(y).ok_or(EvalError::DivByZero)?,
                };
                if d.contains(r) {
                    r
                } else {
                    *saturated = true;
                    x
                }
            }
            Expr::Cmp(op, a, b) => {
                let x = a.eval(st, saturated)?;
                let y = b.eval(st, saturated)?;
                (match op {
                    CmpOp::Eq => x == y,
                    CmpOp::Ne => x != y,
                    CmpOp::Lt => x < y,
                    CmpOp::Le => x <= y,
                    CmpOp::Gt => x > y,
                    CmpOp::Ge => x >= y,
                }) as Val
            }
            Expr::Log(op, a, b) => {
                let x = a.eval(st, saturated)? != 0;
                // Short-circuit like CSPm's `and`/`or`.
                let r = match op {
                    LogOp::And => x && b.eval(st, saturated)? != 0,
                    LogOp::Or => x || b.eval(st, saturated)? != 0,
                    LogOp::Implies => !x || b.eval(st, saturated)? != 0,
                    LogOp::Iff => x == (b.eval(st, saturated)? != 0),
                };
                r as Val
            }
            Expr::If(c, a, b) => {
                if c.eval(st, saturated)? != 0 {
                    a.eval(st, saturated)?
                } else {
                    b.eval(st, saturated)?
                }
            }
            Expr::Tuple(parts) => {
                let mut code = 0;
                for (e, d) in parts {
                    let v = e.eval(st, saturated)?;
                    if !d.contains(v) {
                        return Err(EvalError::OutOfType);
                    }
                    code = code * d.size() as Val + (v - d.lo);
                }
                code
            }
            Expr::Proj(t, stride, d) => (t.eval(st, saturated)? / stride).rem_euclid(d.size().max(1) as Val) + d.lo,
            Expr::Elem(e, d) => {
                let v = e.eval(st, saturated)?;
                if !d.contains(v) || v - d.lo >= 62 {
                    return Err(EvalError::OutOfType);
                }
                1 << (v - d.lo)
            }
            Expr::Set(op, a, b) => {
                let x = a.eval(st, saturated)?;
                let y = b.eval(st, saturated)?;
                match op {
                    SetOp::Union => x | y,
                    SetOp::Inter => x & y,
                    SetOp::Diff => x & !y,
                    SetOp::Subset => (x & !y == 0) as Val,
                    SetOp::Meets => (x & y != 0) as Val,
                }
            }
            Expr::Card(s) => s.eval(st, saturated)?.count_ones() as Val,
            Expr::Checked(e, d) => {
                let v = e.eval(st, saturated)?;
                if !d.contains(v) {
                    return Err(EvalError::OutOfDomain(v, *d));
                }
                v
            }
            Expr::Seq(op, args, d) => d.eval(*op, args, st, saturated)?,
        })
    }

    /// The value when it does not depend on the state.
    pub fn constant(&self) -> Option<Val> {
        let mut sat = false;
        if self.is_static() {
            self.eval(&[], &mut sat).ok()
        } else {
            None
        }
    }

    fn is_static(&self) -> bool {
        match self {
            Expr::Const(_) => true,
            Expr::Slot(_) | Expr::Clock(_) => false,
            Expr::Neg(e, _) | Expr::Not(e) => e.is_static(),
            Expr::Arith(_, a, b, _) | Expr::Cmp(_, a, b) | Expr::Log(_, a, b) => a.is_static() && b.is_static(),
            Expr::If(c, a, b) => c.is_static() && a.is_static() && b.is_static(),
            Expr::Tuple(parts) => parts.iter().all(|(e, _)| e.is_static()),
            Expr::Proj(e, ..) | Expr::Elem(e, _) | Expr::Card(e) | Expr::Checked(e, _) => e.is_static(),
            Expr::Set(_, a, b) => a.is_static() && b.is_static(),
            Expr::Seq(_, args, _) => args.iter().all(Expr::is_static),
        }
    }

    /// `self`, checked to be in `d` when it is used ([`Expr::Checked`]);
    /// a constant in `d` as it is.
    pub fn checked(self, d: Dom) -> Expr {
        match self {
            Expr::Const(v) if d.contains(v) => self,
            e => Expr::Checked(Box::new(e), d),
        }
    }
}

/// A communication channel of a machine, as seen from the module.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    /// The platform's name for it (`obstacle`, `move`).
    pub name: String,
    /// Direction, from the software's point of view.
    pub dir: Dir,
    /// Whether it is a platform operation call (`moveCall`).
    pub is_call: bool,
    /// The domains of its arguments (one for a typed event).
    pub params: Vec<Dom>,
    /// How each argument is named in events (a tuple's components are
    /// fields of their own).
    pub shape: Vec<crate::events::Param>,
    /// RoboSim inputs: the slot of the register's presence flag (its value
    /// is in the next slot); for a variable, the slot of its value (the
    /// variable itself).
    pub register: Option<u16>,
    /// Between two machines of the design (hidden), not with the platform.
    pub internal: bool,
    /// An asynchronous connection between machines or controllers: the
    /// buffer between the sender and the receiver (then `internal`).
    pub buffer: Option<Buffer>,
    /// A variable of the robotic platform: an output's events are its
    /// updates (`set_x.v`, paper §5.2: platform variables are outputs); a
    /// RoboSim input's register holds its value, read with no presence
    /// flag (`registerRead.i_x.v`).
    pub var: bool,
    /// A machine's event connected to nothing (then `internal`): the
    /// controller hides it, so the machine's communications on it are
    /// hidden steps of its own, an input taking any value (RT-15).
    pub alone: bool,
    /// How many machines take part in an internal synchronous
    /// communication besides the sender: with several, all receive at once
    /// (RT-14: a multi-way synchronisation).
    pub receivers: u8,
    /// RoboSim: an output of the output context, written to its register
    /// (`registerWrite.o_x`), not a call of a software operation.
    pub register_write: bool,
    /// RoboSim: a call of a software operation nothing defines for the
    /// machine (RT-19): the urgent visible event `opCall.args` (RoboTool's
    /// `CALL__op = EDeadline(opCall, 0)`), no register: any number of
    /// calls per cycle.
    pub soft_call: bool,
    /// RoboSim: a connection between two machines or controllers of the
    /// design (RT-22): the slot of its memory cell's presence flag (the
    /// value in the next slot). The sender writes the cell in cycle k; at
    /// the start of cycle k+1 it is copied into the receiver's `register`
    /// and erased.
    pub cell: Option<u16>,
}

impl Channel {
    /// A channel to or from the platform with parameters named by `shape`
    /// (no register, buffer or variable: callers set those).
    pub fn new(name: &str, dir: Dir, is_call: bool, shape: Vec<crate::events::Param>) -> Channel {
        Channel {
            name: name.to_string(),
            dir,
            is_call,
            params: shape.iter().map(crate::events::Param::dom).collect(),
            shape,
            register: None,
            internal: false,
            buffer: None,
            var: false,
            alone: false,
            receivers: 1,
            register_write: false,
            soft_call: false,
            cell: None,
        }
    }
}

/// What an asynchronous connection does with the values sent and not yet
/// received. RoboTool's generated CSPm puts a one-place buffer that
/// overwrites between two controllers (robotool-facts.md RT-12,
/// [`AsyncBuffer::ROBOTOOL`]); a user may check under another.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct AsyncBuffer {
    /// How many values it holds (1 to [`AsyncBuffer::MAX`]).
    pub size: u8,
    /// When full: the oldest value is dropped (`true`), or the sender
    /// waits (`false`).
    pub overwrite: bool,
}

impl AsyncBuffer {
    /// The largest buffer (each value is a slot of every state).
    pub const MAX: u8 = 8;

    /// RoboTool's buffer (RT-12): one place; the sender never blocks and an
    /// unread value is lost when the next one arrives.
    pub const ROBOTOOL: AsyncBuffer = AsyncBuffer { size: 1, overwrite: true };

    /// Reads `SIZE[:overwrite|:block]` (overwrite when the policy is left out).
    pub fn parse(text: &str) -> Result<AsyncBuffer, String> {
        let (size, policy) = text.split_once(':').unwrap_or((text, "overwrite"));
        let size: u8 =
            size.trim().parse().ok().filter(|n| (1..=AsyncBuffer::MAX).contains(n)).ok_or_else(|| {
                format!("the buffer size must be a number from 1 to {}, not `{size}`", AsyncBuffer::MAX)
            })?;
        let overwrite = match policy.trim() {
            "overwrite" => true,
            "block" => false,
            p => return Err(format!("a full buffer either `overwrite`s its oldest value or `block`s, not `{p}`")),
        };
        Ok(AsyncBuffer { size, overwrite })
    }

    /// The buffer in words, for reports: which one the verdict holds under,
    /// and whether it is RoboTool's.
    pub fn describe(self) -> String {
        let what = format!(
            "asynchronous connections buffer {} value{}; when full, {}",
            self.size,
            if self.size == 1 { "" } else { "s" },
            if self.overwrite { "a new value replaces the oldest" } else { "the sender waits" }
        );
        if self == AsyncBuffer::ROBOTOOL {
            format!("{what} (RoboTool's buffer between controllers, RT-12)")
        } else {
            format!("{what} (assumed with `--async-buffer`; RoboTool's buffer between controllers is `1:overwrite`)")
        }
    }
}

/// The buffer of an asynchronous channel in the state vector.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Buffer {
    /// The slot of the number of values held; the values follow, oldest
    /// first (unused ones are 0).
    pub slot: u16,
    /// Its policy.
    pub policy: AsyncBuffer,
}

/// Direction of a channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Dir {
    /// From the platform to the software.
    In,
    /// From the software to the platform.
    Out,
}

/// One instruction of a machine's code.
#[derive(Debug, Clone, PartialEq)]
pub enum Instr {
    /// `x = e`; `shared` variables are written in a step of their own so
    /// that other machines can observe the order of writes.
    Assign {
        /// The variable's slot.
        slot: u16,
        /// The value.
        expr: Expr,
        /// The variable's domain (an out-of-range value leaves it unchanged).
        dom: Dom,
        /// Whether another machine can read it.
        shared: bool,
        /// RT-16: the writer's copy of a variable its controller provides
        /// to several machines: the controller's slot, the slot of the
        /// machines still to update, and those to update after this write
        /// (a bit per machine). The write waits while an earlier one is
        /// being forwarded ([`Design::forward_steps`]).
        forward: Option<(u16, u16, i32)>,
    },
    /// `#C`.
    ResetClock(u16),
    /// An output: `e!v`, `e`, a platform operation call (urgent), or the
    /// update of a platform variable (urgent, with `store`).
    Out {
        /// Channel index.
        chan: u16,
        /// Argument values.
        args: Vec<Expr>,
        /// Urgent (operation calls): time cannot pass before it.
        urgent: bool,
        /// A platform variable's update: the slot (and domain) that keeps
        /// the value, written in the same step as the event, so that no
        /// other machine sees the variable changed before the update or
        /// unchanged after it.
        store: Option<(u16, Dom)>,
    },
    /// An input statement `e?x` / `e.v` / `e`.
    In {
        /// Channel index.
        chan: u16,
        /// `e.v`: the value required.
        value: Option<Expr>,
        /// `e?x`: where the value goes.
        bind: Option<(u16, Dom)>,
    },
    /// Sets the machine's wait counter (`wait(e)`).
    SetWait(Expr),
    /// `wait([a, b])`: an internal choice of the counter in `a..=b`.
    ChooseWait(Expr, Expr),
    /// Waits while the counter is positive.
    Wait,
    /// Continues at the target when the condition is false.
    JumpIfNot(Expr, u32),
    /// Continues at the target.
    Jump(u32),
    /// Enters a node (state, junction or final).
    Enter(u16),
    /// Starts the exits of the current transition from the active leaf.
    BeginExits,
    /// The end of a node's exit action: go on exiting or run the
    /// transition's body.
    ExitDone(u16),
    /// A state whose entry work is done: its transitions may fire.
    Rest,
    /// At a junction: one enabled outgoing transition is taken.
    Junction(u16),
    /// The machine has terminated.
    Terminate,
    /// RoboSim `exec`: the machine's cycle ends here; it resumes at the
    /// target after the next cycle's reads.
    Exec(u32),
    /// RoboSim: the cycle ended by taking an `exec` transition (the current
    /// transition); its exits, action and target run after the next reads.
    ExecTransition,
    /// A call of an operation defined in the model: its arguments go to its
    /// parameters, the caller's place is saved, its body starts.
    CallOp {
        /// Index into the machine's operations.
        op: u16,
        /// Argument values.
        args: Vec<Expr>,
    },
    /// The end of an operation's body: back to the caller.
    Return(u16),
    /// `S <{d}`: `S`, which starts here, must end within `d` time units.
    Deadline(Expr),
    /// The end of a statement with a deadline.
    EndDeadline,
    /// The end of a state's entry work: its deadline timer starts, at the
    /// least of the deadlines `<{d}` of its transitions.
    StartTimer {
        /// The timer's slot.
        slot: u16,
        /// The deadlines of the state's transitions.
        limits: Vec<Expr>,
    },
    /// The end of a simple (or final) state's entry action, RoboTool's
    /// `entered`: the state's `sinceEntry` clock restarts, and so do those
    /// of the composite states entered with it (their `entered` follows
    /// the first substate's); their during actions start as activities
    /// running alongside the substates, innermost first, unless already
    /// running (RT-17: once per entry of the composite).
    Entered(u16),
    /// The end of an activity's code: it lets time pass until its state
    /// is left (`TStop`).
    ActivityEnd,
}

/// What a node is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum NodeKind {
    State,
    Junction,
    Initial,
    Final,
}

/// An operation defined in the model, compiled into its caller machine.
#[derive(Debug, Clone, PartialEq)]
pub struct Operation {
    /// Its name.
    pub name: String,
    /// Its parameters' slots and domains.
    pub params: Vec<(u16, Dom)>,
    /// The start of its body (its initial transition).
    pub start_pc: u32,
    /// Where the caller resumes, while the body runs.
    pub ret_slot: u16,
    /// The caller's active state, while the body runs.
    pub leaf_slot: u16,
    /// Its own variables and clocks: (slot, initial value), set again at
    /// each call: a call runs a fresh process (RoboTool's `CALL__op =
    /// OP_op::O__(id__)`, the reference's `pkg223__MovementC.csp`).
    pub locals: Vec<(u16, i32)>,
}

/// A state, junction, initial or final node.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// Its name.
    pub name: String,
    /// The operation whose body it belongs to (none: the machine's).
    pub op: Option<u16>,
    /// What it is.
    pub kind: NodeKind,
    /// The enclosing state.
    pub parent: Option<u16>,
    /// Code run on entry (states: the entry action then the initial
    /// transition of its region, or `Rest`).
    pub entry_pc: u32,
    /// Code run on exit, ending in `ExitDone`.
    pub exit_pc: u32,
    /// The clock of `sinceEntry(S)`, if used.
    pub since_entry: Option<u16>,
    /// A composite state's `sinceEntry` clock restarts at the first
    /// substate's `entered` after the composite's entry: this slot is 1
    /// from the composite's entry until then, 0 otherwise.
    pub entered_flag: Option<u16>,
    /// Simple and final states: the pc of the [`Instr::Entered`] ending
    /// the entry action (the state is entered once the thread is past it).
    pub entered_pc: Option<u32>,
    /// The code of its during action (`start..end`): transitions may
    /// interrupt it.
    pub during: Option<(u32, u32)>,
    /// The slot of its deadline timer, when transitions from it have
    /// deadlines `<{d}`: the time left to take one (-1: not active).
    pub timer: Option<u16>,
    /// The activity running a composite state's during action (index
    /// into [`Machine::activities`]).
    pub activity: Option<u16>,
    /// Outgoing transitions.
    pub out: Vec<u16>,
    /// The declaration's name range.
    pub range: TextRange,
}

/// A composite state's during action, which runs alongside its substates
/// from the end of the first substate's entry action until a transition
/// leaves the composite state (RT-17): a thread of the machine with its own control slots.
#[derive(Debug, Clone, PartialEq)]
pub struct Activity {
    /// The state.
    pub state: u16,
    /// The start of its code (ending in [`Instr::ActivityEnd`]).
    pub start_pc: u32,
    /// Where the activity is (-1: not running).
    pub pc_slot: u16,
    /// Its wait counter.
    pub wait_slot: u16,
    /// Its statement deadline budget (-1: none).
    pub deadline_slot: u16,
}

/// A transition's trigger.
#[derive(Debug, Clone, PartialEq)]
pub enum Trigger {
    /// An input communication.
    In {
        /// Channel index.
        chan: u16,
        /// `e.v`.
        value: Option<Expr>,
        /// `e?x`.
        bind: Option<(u16, Dom)>,
    },
    /// An output communication (`e!v` as a trigger).
    Out {
        /// Channel index.
        chan: u16,
        /// Argument values.
        args: Vec<Expr>,
    },
}

/// A transition.
#[derive(Debug, Clone, PartialEq)]
pub struct Transition {
    /// Its name.
    pub name: String,
    /// Source node.
    pub source: u16,
    /// Target node.
    pub target: u16,
    /// The trigger, if any.
    pub trigger: Option<Trigger>,
    /// The guard, if any.
    pub guard: Option<Expr>,
    /// Clock resets, action and entry of the target.
    pub body_pc: u32,
    /// RoboSim: triggered by `exec` (ends the cycle when taken).
    pub exec: bool,
    /// RoboSim: `$e?x` in the guard: the variable (slot, domain) and the
    /// slot holding the input's value, assigned when the transition is taken.
    pub binds: Vec<(u16, Dom, u16)>,
    /// The declaration's range.
    pub range: TextRange,
    /// The file it is declared in (index into the design's files).
    pub file: u16,
}

/// A compiled state machine.
#[derive(Debug, Clone, PartialEq)]
pub struct Machine {
    /// Its name (the reference's name in its controller).
    pub name: String,
    /// The name of its declaration (`M` for `sref s = M`).
    pub decl_name: String,
    /// Nodes; the index is the node id.
    pub nodes: Vec<Node>,
    /// Transitions.
    pub transitions: Vec<Transition>,
    /// Instructions.
    pub code: Vec<Instr>,
    /// The source range of each instruction (statement, transition, state).
    pub code_ranges: Vec<TextRange>,
    /// The file of each instruction (index into the design's files): the
    /// body of an operation may be in another file than its machine.
    pub code_files: Vec<u16>,
    /// Where execution starts (the root region's initial transition).
    pub start_pc: u32,
    /// RoboSim: an `Exec(start_pc)` instruction: where a machine waits for
    /// its first cycle.
    pub first_cycle_pc: u32,
    /// RoboSim: the machine's `ExecTransition` instruction.
    pub exec_transition_pc: u32,
    /// Operations defined in the model that the machine calls.
    pub ops: Vec<Operation>,
    /// The during actions of composite states.
    pub activities: Vec<Activity>,
    /// The slots of the states' deadline timers.
    pub timers: Vec<u16>,
    /// By instruction: the waits whose continuation runs inside the `tock`
    /// step that ends them, a reduction that changes no verdict (see
    /// `eager.rs`); empty when none. Any other wait ends in a hidden step
    /// of its own (RT-18).
    pub eager_waits: Vec<bool>,
    /// By instruction: the communications after which the thread stops,
    /// so that what follows (reading what another thread writes) is a
    /// hidden step of its own, as RoboTool's `get_x` reads are (RT-16,
    /// RT-18); empty when none. A communication whose continuation only
    /// touches the machine's own data goes on in the same step (a
    /// confluent τ, see `eager.rs`).
    pub paused_comms: Vec<bool>,
    /// By instruction: the first instructions of during actions (of simple
    /// states, and activities) before which the thread stops, so that starting the action
    /// is a hidden step the state's transitions may pre-empt, as in
    /// RoboTool's `During`; empty when none (see `eager.rs`).
    pub paused_durings: Vec<bool>,
    /// By instruction: the instructions that read or write what another
    /// thread writes or reads, before which the thread stops unless its
    /// step has touched nothing another thread sees (see `reads.rs`);
    /// empty when none.
    pub volatile: Vec<bool>,
    /// By instruction: the communications that offer values read once, on
    /// arrival, as RoboTool's `get_x?x -> e!x` does, and the assignments
    /// whose read and write are two hidden steps (`get_x?x -> set_y!x`;
    /// see `reads.rs`); empty when none.
    pub latches: Vec<Option<Latch>>,
    /// The variables that a value received goes to by a hidden step of its
    /// own after the communication, as RoboTool's `e?x -> set_x!x`: those
    /// another thread reads (see `reads.rs`); empty when none.
    pub deferred: Vec<(u16, Dom)>,
    /// With [`Machine::deferred`]: per thread (the main one, then each
    /// activity), the value received and not yet written.
    pub pending: Vec<Pending>,
    /// RT-16: the machine's copies of the variables its controller
    /// provides to several machines, with the forwarding a write of each
    /// starts (as [`Instr::Assign`]'s `forward`): a value received into one
    /// is written, by its own hidden step, as an assignment is.
    pub copy_forwards: Vec<(u16, (u16, u16, i32))>,
    /// First of the machine's control slots (leaf, pc, wait counter,
    /// current transition, deadline budget): [`Machine::SLOTS`] of them.
    pub base: u16,
    /// The file the machine is declared in (index into the model's files).
    pub file: u16,
}

/// The values a communication offers, or an assignment writes, read once
/// when its thread gets there (RT-16, RT-18: RoboTool's `get_x?x` before
/// the event or the `set_y`).
#[derive(Debug, Clone, PartialEq)]
pub struct Latch {
    /// 1 once the values are read, 0 before and after the communication.
    pub flag: u16,
    /// A slot per argument (an input's required value: one), with the
    /// channel parameter's domain when known.
    pub slots: Vec<(u16, Option<Dom>)>,
}

/// A value a thread received and has not yet written to its variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Pending {
    /// 0: none; `k + 1`: the value goes to [`Machine::deferred`]`[k]`.
    pub flag: u16,
    /// The value.
    pub value: u16,
}

/// A clock: its slot and the value at which it saturates.
#[derive(Debug, Clone, PartialEq)]
pub struct Clock {
    /// Name, for messages (`MBC`, `sinceEntry(Moving)`).
    pub name: String,
    /// Slot in the state vector.
    pub slot: u16,
    /// The greatest value kept (one more than the greatest compared value).
    pub cap: i32,
}

/// A variable's slot.
#[derive(Debug, Clone, PartialEq)]
pub struct Var {
    /// Qualified name for messages.
    pub name: String,
    /// Slot.
    pub slot: u16,
    /// Domain.
    pub dom: Dom,
    /// Initial value.
    pub init: Val,
}

/// RT-16: a variable a controller provides to several machines lives in
/// the controller's slot; each machine reads its own copy, and a write is
/// forwarded to the other machines' copies by hidden steps of their own,
/// one machine after another.
#[derive(Debug, Clone, PartialEq)]
pub struct Forward {
    /// The controller's slot.
    pub ctrl: u16,
    /// The machines whose copies are still to update (bit `k`: `copies[k]`).
    pub pending: u16,
    /// The machines' copies, in the controller's order.
    pub copies: Vec<u16>,
}

/// What a design is: a module, a controller or a machine on its own.
/// RoboSim's visible alphabet depends on it (robotool-facts RT-21).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Level {
    /// A module: `endexec` and `terminate` hidden.
    Module,
    /// A controller on its own: its own `endexec` and `terminate` visible.
    Controller,
    /// A machine on its own: `endexec` and `terminate` visible.
    Machine,
    /// A RoboSim operation on its own (RT-11, RoboTool's `OP_…::O__`): no
    /// cycle; each `exec` is the visible `endexec` then `startexec`, time
    /// passing before either; `terminate` hidden.
    Operation,
}

/// A RoboChart module (or controller, or machine) compiled for checking.
#[derive(Debug, Clone, PartialEq)]
pub struct Design {
    /// The element's qualified name.
    pub name: String,
    /// Whether it is a module, a controller or a machine.
    pub level: Level,
    /// Machines, all running in parallel.
    pub machines: Vec<Machine>,
    /// External channels (inputs, outputs, operation calls).
    pub channels: Vec<Channel>,
    /// Variables.
    pub vars: Vec<Var>,
    /// Clocks.
    pub clocks: Vec<Clock>,
    /// Number of slots used by the design.
    pub slots: u16,
    /// Files, for source locations.
    pub files: Vec<String>,
    /// Domains used (`core_int` …), for the report.
    pub domains: Vec<(String, Dom)>,
    /// Constants: the qualified name, the value used (its code in the
    /// type's layout), and that value as the modeller writes it (a record
    /// `(| x = 0, y = 0 |)`, a tuple `(0, 0)`; a number as itself).
    pub constants: Vec<(String, Val, String)>,
    /// The values the model takes from RoboTool's defaults because it
    /// gives none (robotool-facts RT-1, RT-4), described for the report.
    pub defaults: Vec<String>,
    /// How `csp` block definitions were read where RoboTool's generators
    /// differ (RT-7: a function by the name the model's call writes).
    pub readings: Vec<String>,
    /// Variables forwarded from a controller to its machines' copies.
    pub forwards: Vec<Forward>,
}

impl Machine {
    /// How many control slots a machine has.
    pub const SLOTS: u16 = 5;
}

impl Design {
    /// The channels to or from the platform in direction `dir` (internal
    /// ones left out), by index.
    pub fn platform_channels(&self, dir: Dir) -> Vec<u16> {
        self.channels.iter().enumerate().filter(|(_, c)| c.dir == dir && !c.internal).map(|(i, _)| i as u16).collect()
    }

    /// The range of every slot of the design's state vector, for packing:
    /// exact where the model bounds the slot, the whole `i32` range where a
    /// value comes from an expression the lowering cannot bound.
    pub fn slot_bounds(&self) -> Vec<(i64, i64)> {
        let full = (i32::MIN as i64, i32::MAX as i64);
        let mut b = vec![full; self.slots as usize];
        let mut set = |slot: u16, lo: i64, hi: i64| {
            if let Some(x) = b.get_mut(slot as usize) {
                *x = (lo, hi.max(lo));
            }
        };
        for m in &self.machines {
            // The largest static wait and deadline, or unbounded.
            let (mut wait, mut deadline, mut timer) = (0i64, 0i64, 0i64);
            for i in &m.code {
                let bound = |e: &Expr| e.constant().map_or(i32::MAX as i64, |v| v.clamp(0, i32::MAX as i64));
                match i {
                    Instr::SetWait(e) => wait = wait.max(bound(e)),
                    Instr::ChooseWait(_, hi) => wait = wait.max(bound(hi)),
                    Instr::Deadline(e) => deadline = deadline.max(bound(e)),
                    // The timer starts at the least of its deadlines.
                    Instr::StartTimer { limits, .. } => timer = timer.max(limits.iter().map(bound).min().unwrap_or(0)),
                    _ => {}
                }
            }
            let (nodes, code, trans) = (m.nodes.len() as i64, m.code.len() as i64, m.transitions.len() as i64);
            set(m.base, -1, nodes);
            set(m.base + 1, 0, code);
            set(m.base + 2, 0, wait);
            set(m.base + 3, -1, trans);
            set(m.base + 4, -1, deadline);
            for op in &m.ops {
                for &(slot, dom) in &op.params {
                    set(slot, dom.lo, dom.hi);
                }
                set(op.ret_slot, -1, code);
                set(op.leaf_slot, -1, nodes);
            }
            for a in &m.activities {
                set(a.pc_slot, -1, code);
                set(a.wait_slot, 0, wait);
                set(a.deadline_slot, -1, deadline);
            }
            for &t in &m.timers {
                set(t, -1, timer);
            }
            let (lo, hi) = m.deferred.iter().fold((0, 0), |(l, h), (_, d)| (d.lo.min(l), d.hi.max(h)));
            for p in &m.pending {
                set(p.flag, 0, m.deferred.len() as i64);
                set(p.value, lo, hi);
            }
            for l in m.latches.iter().flatten() {
                set(l.flag, 0, 1);
                for &(s, d) in &l.slots {
                    if let Some(d) = d {
                        set(s, d.lo.min(0), d.hi.max(0));
                    }
                }
            }
        }
        for v in &self.vars {
            set(v.slot, v.dom.lo.min(v.init), v.dom.hi.max(v.init));
        }
        for c in &self.clocks {
            set(c.slot, 0, c.cap as i64);
        }
        for f in &self.forwards {
            set(f.pending, 0, (1i64 << f.copies.len()) - 1);
        }
        for c in &self.channels {
            if let Some(b) = c.buffer {
                let d = c.params.first().copied().unwrap_or(Dom { lo: 0, hi: 0 });
                set(b.slot, 0, b.policy.size as i64);
                for k in 1..=b.policy.size as u16 {
                    set(b.slot + k, d.lo.min(0), d.hi.max(0));
                }
            }
            if let Some(cell) = c.cell {
                let d = c.params.first().copied().unwrap_or(Dom { lo: 0, hi: 0 });
                set(cell, 0, 1);
                set(cell + 1, d.lo.min(0), d.hi.max(0));
            }
            if let Some(r) = c.register {
                // A variable's register is the variable (bounded above).
                if !c.var {
                    set(r, 0, 1);
                    let d = c.params.first().copied().unwrap_or(Dom { lo: 0, hi: 0 });
                    set(r + 1, d.lo.min(0), d.hi.max(0));
                }
            }
        }
        b
    }

    /// A state vector of `len` slots with the variables' initial values and
    /// every machine before its first step; with `settle`, each machine runs
    /// its initial transition's internal code (RoboChart; a RoboSim machine
    /// waits for its first cycle instead). Run-time errors go to `errors`.
    pub fn initial_state(&self, len: usize, settle: bool, errors: &crate::lts::FirstError) -> Vec<i32> {
        let mut st = vec![0i32; len];
        for v in &self.vars {
            st[v.slot as usize] = v.init as i32;
        }
        for m in &self.machines {
            if settle {
                m.init(&mut st);
                if let Err(e) = m.settle(&mut st, &self.clocks, true) {
                    errors.set(e.0);
                }
            } else {
                m.init_cycle(&mut st);
            }
        }
        st
    }

    /// The state after machine `m` performs `act` in `st` (`value`: the
    /// value an input received).
    pub fn after(
        &self,
        m: &Machine,
        st: &[i32],
        act: crate::machine::Act,
        value: Option<Val>,
    ) -> Result<Box<[i32]>, String> {
        let mut n: Box<[i32]> = st.into();
        m.apply(&mut n, &self.clocks, act, value).map_err(|e| e.0)?;
        Ok(n)
    }

    /// Machine `m` performs `act` on `st` in place (`value`: the value an
    /// input received).
    // Inlined: once per machine step the models generate.
    #[inline]
    pub fn apply(
        &self,
        m: &Machine,
        st: &mut [i32],
        act: crate::machine::Act,
        value: Option<Val>,
    ) -> Result<(), String> {
        m.apply(st, &self.clocks, act, value).map_err(|e| e.0)
    }

    /// One time unit passes: clocks advance (saturating), waits count down.
    pub fn advance_time(&self, st: &mut [i32]) -> Result<(), String> {
        for c in &self.clocks {
            let v = &mut st[c.slot as usize];
            *v = (*v + 1).min(c.cap);
        }
        for m in &self.machines {
            m.tock(st, &self.clocks).map_err(|e| e.0)?;
        }
        Ok(())
    }
}

impl Design {
    /// The communications between machines possible in `st`: an output of
    /// one machine on an internal channel with an input of another that
    /// accepts the value, performed together; on an asynchronous channel,
    /// each side alone, with the buffer. Each is (channel, arguments, the
    /// state after the steps).
    #[allow(clippy::type_complexity)]
    #[inline]
    pub fn internal_steps(
        &self,
        st: &[i32],
        moves: &[(usize, crate::machine::Move)],
    ) -> Result<Vec<(u16, Vec<Val>, Box<[i32]>)>, String> {
        // Most states offer no internal communication: then no call.
        if moves.is_empty() {
            return Ok(Vec::new());
        }
        self.pair_internal(st, moves)
    }

    /// [`Design::internal_steps`] of a non-empty `moves`.
    #[allow(clippy::type_complexity)]
    fn pair_internal(
        &self,
        st: &[i32],
        moves: &[(usize, crate::machine::Move)],
    ) -> Result<Vec<(u16, Vec<Val>, Box<[i32]>)>, String> {
        use crate::machine::Offer;
        let mut out = Vec::new();
        for (mi, mv) in moves {
            let (Offer::Out { chan, .. } | Offer::In { chan, .. }) = &mv.offer else { continue };
            let c = &self.channels[*chan as usize];
            if let Some(b) = c.buffer {
                if let Some(step) = self.buffer_step(st, &self.machines[*mi], mv, b)? {
                    out.push(step);
                }
            } else if c.alone {
                self.alone_steps(st, &self.machines[*mi], mv, &mut out)?;
            }
        }
        for (si, send) in moves {
            let Offer::Out { chan, args } = &send.offer else { continue };
            let c = &self.channels[*chan as usize];
            if !c.internal || c.buffer.is_some() || c.alone {
                continue;
            }
            if c.receivers > 1 {
                self.multiway(st, moves, (*si, send), *chan, args, c.receivers as usize, &mut out)?;
                continue;
            }
            for (ri, recv) in moves {
                let Offer::In { chan: c2, value } = &recv.offer else { continue };
                if c2 != chan || ri == si || value.is_some_and(|v| args.first() != Some(&v)) {
                    continue;
                }
                let n = self.after(&self.machines[*si], st, send.act, None)?;
                let n = self.after(&self.machines[*ri], &n, recv.act, args.first().copied())?;
                out.push((*chan, args.clone(), n));
            }
        }
        Ok(out)
    }

    /// RT-14: a send on a channel with several receiving machines happens
    /// when every one of them accepts the value, all in one step: one step
    /// per combination of the receivers' accepting moves.
    #[allow(clippy::type_complexity, clippy::too_many_arguments)]
    #[cold]
    fn multiway(
        &self,
        st: &[i32],
        moves: &[(usize, crate::machine::Move)],
        (si, send): (usize, &crate::machine::Move),
        chan: u16,
        args: &[Val],
        receivers: usize,
        out: &mut Vec<(u16, Vec<Val>, Box<[i32]>)>,
    ) -> Result<(), String> {
        use crate::machine::Offer;
        // The accepting moves, by receiving machine.
        let mut by_machine: Vec<(usize, Vec<&crate::machine::Move>)> = Vec::new();
        for (ri, recv) in moves {
            let Offer::In { chan: c2, value } = &recv.offer else { continue };
            if *c2 != chan || *ri == si || value.is_some_and(|v| args.first() != Some(&v)) {
                continue;
            }
            match by_machine.iter_mut().find(|(m, _)| m == ri) {
                Some((_, v)) => v.push(recv),
                None => by_machine.push((*ri, vec![recv])),
            }
        }
        if by_machine.len() < receivers {
            return Ok(());
        }
        let first = self.after(&self.machines[si], st, send.act, None)?;
        let mut states = vec![first];
        for (ri, accepting) in &by_machine {
            let mut next = Vec::with_capacity(states.len() * accepting.len());
            for n in &states {
                for recv in accepting {
                    next.push(self.after(&self.machines[*ri], n, recv.act, args.first().copied())?);
                }
            }
            states = next;
        }
        out.extend(states.into_iter().map(|n| (chan, args.to_vec(), n)));
        Ok(())
    }

    /// A machine's communication on an event connected to nothing: a
    /// hidden step of its own (RT-15); an input `e?x` takes any value of
    /// its type, as hiding the event makes the choice internal.
    #[allow(clippy::type_complexity)]
    fn alone_steps(
        &self,
        st: &[i32],
        m: &Machine,
        mv: &crate::machine::Move,
        out: &mut Vec<(u16, Vec<Val>, Box<[i32]>)>,
    ) -> Result<(), String> {
        use crate::machine::Offer;
        match &mv.offer {
            Offer::Out { chan, args } => out.push((*chan, args.clone(), self.after(m, st, mv.act, None)?)),
            Offer::In { chan, value } => {
                let c = &self.channels[*chan as usize];
                let values: Vec<Option<Val>> = match (value, c.params.first()) {
                    (Some(v), _) => vec![Some(*v)],
                    (None, Some(d)) => (d.lo..=d.hi).map(Some).collect(),
                    (None, None) => vec![None],
                };
                for v in values {
                    out.push((*chan, v.into_iter().collect(), self.after(m, st, mv.act, v)?));
                }
            }
            Offer::Tau => {}
        }
        Ok(())
    }

    /// A machine's step on an asynchronous channel: a value sent goes into
    /// the buffer (dropping the oldest when full, if the policy says so);
    /// the oldest value is received (when it is the one required).
    #[allow(clippy::type_complexity)]
    fn buffer_step(
        &self,
        st: &[i32],
        m: &Machine,
        mv: &crate::machine::Move,
        b: Buffer,
    ) -> Result<Option<(u16, Vec<Val>, Box<[i32]>)>, String> {
        use crate::machine::Offer;
        let (count, size) = (st[b.slot as usize] as usize, b.policy.size as usize);
        let value = |k: usize| b.slot as usize + 1 + k;
        Ok(match &mv.offer {
            Offer::Out { chan, args } => {
                if count == size && !b.policy.overwrite {
                    return Ok(None);
                }
                let mut n = self.after(m, st, mv.act, None)?;
                let mut len = count;
                if len == size {
                    n.copy_within(value(1)..value(size), value(0));
                    len -= 1;
                }
                n[value(len)] = args.first().copied().unwrap_or(0) as i32;
                n[b.slot as usize] = (len + 1) as i32;
                Some((*chan, args.clone(), n))
            }
            Offer::In { chan, value: want } => {
                let head = st[value(0)] as Val;
                if count == 0 || want.is_some_and(|w| w != head) {
                    return Ok(None);
                }
                let mut n = self.after(m, st, mv.act, Some(head))?;
                n.copy_within(value(1)..value(size), value(0));
                n[value(size - 1)] = 0;
                n[b.slot as usize] = (count - 1) as i32;
                let args = if self.channels[*chan as usize].params.is_empty() { Vec::new() } else { vec![head] };
                Some((*chan, args, n))
            }
            Offer::Tau => None,
        })
    }

    /// RT-16: the hidden steps that forward a variable's last write to the
    /// next machine's copy (one per variable being forwarded).
    #[inline]
    pub fn forward_steps(&self, st: &[i32]) -> Vec<Box<[i32]>> {
        if self.forwards.is_empty() {
            return Vec::new();
        }
        self.forwards
            .iter()
            .filter(|f| st[f.pending as usize] != 0)
            .map(|f| {
                let p = st[f.pending as usize];
                let mut n: Box<[i32]> = st.into();
                n[f.copies[p.trailing_zeros() as usize] as usize] = st[f.ctrl as usize];
                n[f.pending as usize] = p & (p - 1);
                n
            })
            .collect()
    }

    /// Whether `offer` is on an internal channel (it happens only together
    /// with its partner: see [`Design::internal_steps`]).
    pub fn is_internal(&self, offer: &crate::machine::Offer) -> bool {
        use crate::machine::Offer;
        match offer {
            Offer::In { chan, .. } | Offer::Out { chan, .. } => self.channels[*chan as usize].internal,
            Offer::Tau => false,
        }
    }
}

impl Channel {
    /// The values a register read of this input may carry, as
    /// (present, value): every value when present; when absent one
    /// representative, `absent` (the value is never observed).
    pub fn read_values(&self, absent: Option<Val>) -> impl Iterator<Item = (Val, Option<Val>)> {
        // Present with each value, then absent (no allocation: this runs
        // for every state that reads registers). A variable's register
        // always holds a value.
        let (values, last) = match self.params.first() {
            Some(d) => (Some(d.lo..=d.hi), (0, Some(absent.unwrap_or(d.lo)))),
            None => (None, (0, None)),
        };
        let unit = self.params.is_empty().then_some((1, None));
        let last = (!self.var).then_some(last);
        values.into_iter().flatten().map(|v| (1, Some(v))).chain(unit).chain(last)
    }

    /// The arguments of the register read of `(present, value)`:
    /// `registerRead.i_e.b.v` for events, `registerRead.i_x.v` for
    /// variables.
    pub fn read_args(&self, present: Val, value: Option<Val>) -> ([Val; 2], usize) {
        match (self.var, value) {
            (true, v) => ([v.unwrap_or(0), 0], 1),
            (false, Some(v)) => ([present, v], 2),
            (false, None) => ([present, 0], 1),
        }
    }
}
