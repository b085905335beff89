//! The rule catalogue: every diagnostic code with its severity under each
//! rule set and a one-line explanation (shown in hovers and `--explain`).
//! Codes are those of ../shared/spec/wellformedness.md, `XT-` dropped.

use crate::{RuleSet, Severity};

/// One rule of the catalogue.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rule {
    /// The stable code.
    pub code: &'static str,
    /// Severity under the `paper` rule set.
    pub paper: Severity,
    /// Severity under the `robotool` rule set.
    pub robotool: Severity,
    /// What the rule requires.
    pub summary: &'static str,
}

use Severity::{Error as E, Info as I, Warning as W};

macro_rules! rules {
    ($($code:literal $paper:ident $robotool:ident $summary:literal;)*) => {
        /// Every rule, in catalogue order.
        pub const RULES: &[Rule] = &[$(Rule { code: $code, paper: $paper, robotool: $robotool, summary: $summary }),*];
    };
}

rules! {
    "SYN-01" E E "The file parses with RoboTool's grammar for its language.";
    "SYN-02" W W "Accepted here, but RoboTool's lexer rejects it.";
    "LNK-01" E E "Every reference resolves to an element of the right kind in scope.";
    "LNK-02" W W "A name is imported before use; RoboTool also resolves a plain name in a RoboSim file that no import reaches, which we accept only when every declaration of that name is the same.";
    "LNK-03" W W "A name no file of the workspace declares, in a file importing a package the workspace does not hold (such as a physical model's), cannot be checked.";
    "DUP-01" E E "No two elements of the same kind share a name in the same place.";
    "REQ-01" E E "Required parts are present: RoboSim modules, controllers and machines need a cycleDef; machines and operations need input and output contexts.";
    "RC-PKG-01" W W "Fully qualified names are unique across the workspace.";
    "RC-PKG-02" W W "Every import matches a package or element of the workspace.";
    "RC-TYPE-01" E E "A record has at least one field.";
    "RC-TYPE-02" E E "A vector size is an integer literal or a constant.";
    "RC-TYPE-03" E E "Matrix dimensions are integer literals or constants.";
    "RC:I2" E E "An interface does not declare both events and operations.";
    "RC:I1-req" E E "An interface that a context requires declares no events.";
    "RC:I1-prov" E E "An interface that a context provides declares no events.";
    "RC-IFC-01" E E "An interface that a context provides declares no clocks.";
    "RC:I2-uses" E E "An interface that a context uses declares no operations.";
    "RC:RP1" E E "A robotic platform requires no interface.";
    "RC:RP2" E E "Interfaces a robotic platform uses declare no clocks.";
    "RC:C1" E E "A controller has at least one state machine.";
    "RC:C2" E E "A controller provides no interface.";
    "RC:C6" E E "Within a controller, each event of each node is in at most one connection.";
    "RC:C10" E E "Interfaces a controller uses declare no clocks.";
    "RC:C11" E E "Interfaces a controller requires declare no clocks.";
    "RC:M1" E E "A module has exactly one robotic platform.";
    "RC-MOD-01" E E "A module has at least one controller.";
    "RC-MOD-02" E E "A module contains no state machine directly.";
    "RC:M3" E E "Within a module, each event of each node is in at most one connection.";
    "RC:Cn1" E E "A module's connections join only its platform and controllers.";
    "RC:Cn2" E E "Connections with the robotic platform are asynchronous.";
    "RC:Cn3" E E "A controller's connections join only the controller and its machines.";
    "RC:Cn10" E E "Each end of a connection names an event of that end's node.";
    "RC:Cn11" W W "Asynchronous connections between two machines have no semantics.";
    "RC-CONN-03" W W "A synchronous connection of an event to itself means nothing.";
    "RC:STM1" E E "A state machine provides no interface.";
    "RC:STM3" E E "A state machine has exactly one initial junction at its top level.";
    "RC:STM3-nested" W W "A composite state or operation with nodes has exactly one initial junction.";
    "RC:STM4" E E "A machine, composite state or operation with nodes has at least one state or final state.";
    "RC:STM7" E E "Interfaces a state machine requires declare no clocks.";
    "RC:O1:STM1" E E "An operation definition provides no interface.";
    "RC:S2" E E "A state has at most one entry, one during and one exit action.";
    "RC:IJ1" E E "No transition enters an initial junction.";
    "RC:IJ2" E E "An initial junction has exactly one outgoing transition.";
    "RC:J1" E E "A junction has at least one outgoing transition.";
    "RC-JUNC-01" E E "A junction has at least one incoming transition.";
    "RC:FS1" E E "No transition leaves a final state.";
    "RC:J3" E E "A transition with a trigger (RoboSim: exec) leaves a state, not a junction.";
    "RC:TT1" E E "A transition with a deadline has a trigger.";
    "RC:PJ1" E E "A transition leaving a probabilistic junction has a probability.";
    "RC:PJ2" E E "A transition leaving a probabilistic junction has no condition.";
    "RC:PT1" E E "Only transitions leaving a probabilistic junction carry a probability.";
    "RS:M1" E W "A RoboSim module's cycleDef is a boolean expression.";
    "RS:M2" E W "A module's and its controllers' cycle specifications admit a common positive period.";
    "RS:M3" E W "The outputs of a module's controllers are disjoint.";
    "RS:C1" E W "A RoboSim controller's cycleDef is a boolean expression.";
    "RS:C2" E W "A controller's and its machines' cycle specifications admit a common positive period.";
    "RS:C3" E W "Connections with a machine respect its inputs and outputs.";
    "RS:C4" E W "The outputs of a controller's machines are disjoint.";
    "RS:SM1" E W "A RoboSim machine's cycleDef is a boolean expression.";
    "RS:SM2" E W "A machine's inputs are only events and variables.";
    "RS:SM3" E E "Only required variables can be inputs or outputs (RoboTool checks this as its RS-IO-01/02).";
    "RS:SM4" E W "Variables a machine requires are inputs or outputs.";
    "RS:SM5" E W "Operations a machine calls are outputs, unless its controller defines them.";
    "RS:SM6" E W "Inputs, outputs and required variables are referred to with `$`; local names without it.";
    "RS-CYC-01" W W "A cycle specification admits at least one positive period on its own.";
    "RS-CYC-02" W W "A cycle specification mentions only `cycle`, literals and constants.";
    "RS-CYC-03" I I "The cycle specifications could not be decided.";
    "RS-IO-03" E E "An output communication does not emit an input event.";
    "RS-IO-04" E E "Only inputs are read in expressions: an output event or variable cannot be tested.";
    "RC-STMT-01" E E "An operation parameter is not assigned.";
    "RC-STMT-06" E W "A constant is not assigned.";
    "RC-TRANS-01" E E "A transition condition is boolean.";
    "RS-TRANS-01" E E "A transition condition is boolean.";
    "RC-EXP-13" E W "Function pre- and postconditions are boolean.";
    "RC-EXP-14" E W "Every expression in a typed position has a type; the innermost ill-typed part is reported.";
    "RC-EXP-01" E E "A tuple is indexed by exactly one index.";
    "RC-EXP-02" E E "A tuple index is a numeral.";
    "RC-EXP-12" E E "Each value of a record literal fits its field's type.";
    "RC-EXP-03" E E "A tuple index is a numeral within the tuple's size.";
    "RC-EXP-05" E E "An enumeration literal that takes arguments is not used without them.";
    "RC-EXP-06" W W "A literal without parameters is not applied to `()`.";
    "RC-EXP-07" E E "A constructor application has as many arguments as the literal declares.";
    "RC-EXP-08" E E "Each constructor argument fits the literal's parameter type.";
    "RC-EXP-09" E E "A function call has as many arguments as the function has parameters.";
    "RC-EXP-10" E E "Each argument's type is compatible with its parameter's (generic parameters instantiated).";
    "RC-EXP-11" E E "A cast `e as T` converts between compatible types.";
    "RC-EXP-11-narrow" W W "A numeric narrowing cast (real to int, int to nat) is a warning.";
    "RC-VAR-01" E E "A variable's or constant's initial value is compatible with its type.";
    "RC-STMT-02" E E "An assignment's value is compatible with the target's type.";
    "RC-STMT-03" E E "The condition of an `if` statement is boolean.";
    "RC-STMT-04" E E "`wait` takes an integer or a set of integers.";
    "RC-STMT-05" E E "An operation call has the right number of arguments, of compatible types.";
    "RC-STMT-05-narrow" W W "An operation argument of a wider number type than its parameter (`int` for `nat`, `real` for `int`) is accepted, as RoboTool does; a negative or fractional value would be wrong at run time.";
    "RC:TE1" E E "`since` and `sinceEntry` do not occur in actions.";
    "RC:TE3" E E "`sinceEntry(S)` names a non-final state of the enclosing machine or operation.";
    "RC:TE5" E E "`sinceEntry(S)` in a transition names a state of the transition's own container.";
    "RC:TE4" E E "A timed expression is only compared with a number.";
    "RC:Tg2" E E "A communication without a value uses an untyped event.";
    "RC:Tg5" E E "A communication with a value uses a typed event.";
    "RC-COMM-01" E E "In `e?x` the event's values fit the variable.";
    "RC-COMM-02" E E "In `e!v` the value fits the event.";
    "RC-COMM-03" E E "In `e.v` the value fits the event.";
    "RS-IO-06" E W "An output communication `$e!v` / `$e` matches the event's type.";
    "RC:PT2" E E "A probability lies in [0, 1].";
    "RC-TYPE-04" E W "A constant used as a vector or matrix size has type nat.";
    "RC:C3" E E "A controller provides every variable its machines require.";
    "RC:C4" E E "A controller defines or requires every operation its machines require.";
    "RC:C4-weak" E E "Every operation an operation of the controller requires is defined or required by the controller.";
    "RC:C8" E E "A controller does not include the same operation definition twice.";
    "RC:M2" E E "The robotic platform provides every variable and operation the controllers require.";
    "RC:Cn4" E E "A broadcast event connects only to a broadcast event.";
    "RC-CONN-01" E E "Broadcast connections relay between levels.";
    "RC-CONN-02" E E "Connected events have compatible types.";
    "RC:Cn5" E E "A bidirectional module connection to a controller is bidirectional inside it too.";
    "RC:Cn6" E E "A one-way module connection into a controller continues one-way from it.";
    "RC:Cn7" E E "A one-way module connection out of a controller continues one-way into it.";
    "RC:Cn8" E E "A one-way connection into a machine is not used by the machine for output.";
    "RC:Cn9" E E "A one-way connection out of a machine is not used by the machine for input.";
    "RC:STM8" E E "An operation's required variables are provided by each machine or operation that calls it.";
    "RC:STM9" E E "An operation's events exist in each machine or operation that calls it.";
    "RC:STM10" E E "An operation's required clocks are clocks of each caller.";
    "RS-IO-05" E E "An operation's inputs and outputs are inputs and outputs of each caller.";
    "RC:O2" E W "Operations are not recursive.";
    "RC:PJ3" W W "The probabilities leaving a probabilistic junction add up to 1.";
    "RS-IO-07" E W "`$e?x` reads a typed input event into a local variable, in a transition condition.";
    "RS-IO-08" W W "RoboSim machines see events only through their input and output contexts.";
    "RS-IO-09" E W "A controller provides the variables its machines read and write through I/O contexts.";
    "RS-STMT-02" E W "RoboSim has no statement deadlines.";
    "RS-IO-02" E E "Interfaces used in an input context declare only events.";
    "CSP-L01" E W "The CSPm of a `csp` block is made of CSPm tokens; comments and literals are closed.";
    "CSP-P01" E W "The CSPm of a `csp` block parses with FDR's grammar.";
    "CSP-U01" W W "A `csp` block uses CSPm this tool does not check (FDR may accept it).";
    "CSP-N01" E W "Every name a `csp` block uses is defined: by the block, another block of its file, the model (as RoboTool names it), RoboTool's library or FDR.";
    "CSP-N02" E W "A name is defined at most once in the same scope of a `csp` block.";
    "CSP-N03" E W "The left-hand side of a `csp` block definition is a name, a pattern or a function with patterns.";
    "CSP-N04" W W "A `csp` block defines a model's function by RoboTool 3's CSPm name, its package first (`Mathematics_floor`).";
    "CSP-T01" E W "The CSPm of a `csp` block is well typed.";
}

/// The rule with `code`.
pub fn rule(code: &str) -> Option<&'static Rule> {
    RULES.iter().find(|r| r.code == code)
}

/// The severity of `code` under `rules` (unknown codes are errors).
pub fn severity(code: &str, rules: RuleSet) -> Severity {
    match rule(code) {
        Some(r) => match rules {
            RuleSet::Paper => r.paper,
            RuleSet::RoboTool => r.robotool,
        },
        None => Severity::Error,
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn codes_are_unique() {
        let mut seen = std::collections::HashSet::new();
        for r in super::RULES {
            assert!(seen.insert(r.code), "duplicate code {}", r.code);
        }
    }
}
