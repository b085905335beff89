//! RoboSim connections between machines or controllers of the design
//! (robotool-facts RT-22): through a per-event memory cell. The sender's
//! output writes the cell; at the start of the next cycle the cell is
//! copied into the receiver's input register and erased, so the receiver
//! sees the value exactly one cycle later, and only in that cycle. The
//! cycle itself (copying and erasing) is in [`crate::sim`].

use robosim_hir::TextRange;

use super::{MachineCx, Unsupported};

impl MachineCx<'_, '_> {
    /// Gives the internal channel `chan` (the event `name` of a RoboSim
    /// machine) its register and memory cell, once.
    pub(super) fn memory_cell(&mut self, chan: u16, name: &str, range: TextRange) -> Result<(), Unsupported> {
        // Several receivers share the cell, and the input register it is
        // copied into (every end of the connection is this one channel):
        // whether RoboTool keeps one cell per event (RT-22) or one per
        // connection, each written by the same write before the cycle
        // ends (hidden steps have priority over `tock`) and all read at
        // the next cycle's start, every receiver sees the same value in
        // the same cycle, and receivers never write it.
        if self.design().channels[chan as usize].params.len() > 1 {
            return Err(self.err(
                range,
                format!(
                    "`{name}` carries several values between RoboSim machines or controllers: only events \
                     with at most one value are supported through their memory cell (RT-22)"
                ),
            ));
        }
        if self.design().channels[chan as usize].register.is_none() {
            let reg = self.new_slot();
            self.new_slot();
            self.design().channels[chan as usize].register = Some(reg);
        }
        if self.design().channels[chan as usize].cell.is_none() {
            let cell = self.new_slot();
            self.new_slot();
            self.design().channels[chan as usize].cell = Some(cell);
        }
        let c = &mut self.design().channels[chan as usize];
        c.internal = true;
        c.receivers = 1;
        Ok(())
    }
}
