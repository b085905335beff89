//! What the lowering sees of an element, in the vocabulary of the CSPm
//! export (RoboTool's names): its visible events with their values, its
//! constants with the values used, the bounded number types and its
//! period. Tests compare it with the export's output (the two back ends
//! must agree on them); tools may show it.

use robosim_hir::cycle::{simulation_period, Feasibility};
use robosim_hir::index::ItemLoc;
use robosim_hir::{Db, Workspace};

use super::{lower_element, ConstValue, DomainDefaults, Unsupported};
use crate::events::{EventTable, Param};
use crate::ir::{Design, Dir, Dom, Val};

/// A lowered element as the engine sees it (see [`inspect_element`]).
#[derive(Debug, Clone)]
pub struct ElementView {
    /// The element's qualified name.
    pub name: String,
    /// Whether it is a RoboSim element (its events are register reads
    /// and writes, and it has a period).
    pub robosim: bool,
    /// The events it shares with its environment (the platform), one per
    /// channel, in the design's order.
    pub events: Vec<EventView>,
    /// Each constant (`Machine::k`, under its controller's and module's
    /// references), the value the engine uses (its code), and that value
    /// as written (records and tuples decoded).
    pub constants: Vec<(String, Val, String)>,
    /// The values taken from RoboTool's defaults because the model gives
    /// none (RT-1, RT-4), described (`constant M::k = 0 (RT-1)`).
    pub defaults: Vec<String>,
    /// The number types (`core_nat`, `core_int`, `core_real`) as bounded
    /// for this element.
    pub domains: Vec<(String, Dom)>,
    /// The period it is simulated with (RoboSim): hir's choice from the
    /// `cycleDef`s of the element and its components; `None` for
    /// RoboChart, or when no `cycleDef` says anything.
    pub period: Option<Feasibility>,
}

/// One visible channel of an element, named as RoboTool's CSPm names it
/// (`obstacle.in`, `moveCall`, `set_x`, `registerRead.i_obstacle`,
/// `registerWrite.o_move`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EventView {
    /// The channel with its fixed prefix (direction, register).
    pub label: String,
    /// The direction, from the software's point of view.
    pub dir: Dir,
    /// The fields after the label, each with its values.
    pub fields: Vec<Param>,
}

impl EventView {
    /// Every event of the channel, printed as CSPm prints it
    /// (`moveCall.1.0`, `registerRead.i_obstacle.true`); `None` when there
    /// are more than `limit`.
    pub fn events(&self, limit: u64) -> Option<Vec<String>> {
        let mut table = EventTable::default();
        let g = table.add(self.label.clone(), self.fields.clone()).ok()?;
        let group = table.group(g);
        if group.size > limit {
            return None;
        }
        Some((0..group.size).filter_map(|i| table.name(group.base + i as u32)).collect())
    }
}

/// Lowers the RoboChart or RoboSim module, controller or machine `loc`
/// (with `inner`, the machine of that name inside the controller `loc`)
/// and describes it (see [`ElementView`]); the constant values `consts`
/// and the bounds `defaults` are those an assertion would give.
pub fn inspect_element(
    db: &dyn Db,
    ws: Workspace,
    loc: ItemLoc,
    inner: Option<&str>,
    consts: &[ConstValue],
    defaults: &DomainDefaults,
) -> Result<ElementView, Unsupported> {
    let robosim = loc.file.kind(db) == robosim_hir::FileKind::RoboSim;
    let design = lower_element(db, ws, loc, inner, consts, defaults)?;
    let period = if robosim && inner.is_none() {
        let bound: Vec<(String, String, i64)> =
            consts.iter().map(|c| (c.of.last().cloned().unwrap_or_default(), c.name.clone(), c.value)).collect();
        loc.def(db).and_then(|def| simulation_period(db, ws, loc.file, def, &bound))
    } else {
        None
    };
    Ok(ElementView {
        name: design.name.clone(),
        robosim,
        events: visible_events(&design, robosim),
        constants: design.constants.clone(),
        defaults: design.defaults.clone(),
        domains: design.domains.clone(),
        period,
    })
}

/// The channels of `design` that face the platform, labelled as the
/// engine labels their events (`design::channel_name`, and for RoboSim
/// the registers of `sched`).
fn visible_events(design: &Design, robosim: bool) -> Vec<EventView> {
    let mut out: Vec<EventView> = Vec::new();
    for c in design.channels.iter().filter(|c| !c.internal) {
        let (label, fields) = if robosim {
            match c.dir {
                // A register read says whether the event happened, then its
                // value; a variable's register always holds a value.
                Dir::In => {
                    let mut fields = if c.var { Vec::new() } else { vec![Param::Bool] };
                    fields.extend(c.shape.iter().cloned());
                    (format!("registerRead.i_{}", c.name), fields)
                }
                Dir::Out if c.soft_call => (format!("{}Call", c.name), c.shape.clone()),
                Dir::Out => (format!("registerWrite.o_{}", c.name), c.shape.clone()),
            }
        } else {
            (crate::design::channel_name(c), c.shape.clone())
        };
        // A channel used both ways (`[mult]`) appears once per direction.
        if !out.iter().any(|e| e.label == label) {
            out.push(EventView { label, dir: c.dir, fields });
        }
    }
    out
}
