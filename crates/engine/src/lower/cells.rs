//! RoboSim connections between machines or controllers of the design
//! (robotool-facts RT-22): through a per-event memory cell. The sender's
//! output writes the cell; at the start of the next cycle the cell is
//! copied into the receiver's input register and erased, so the receiver
//! sees the value exactly one cycle later, and only in that cycle. The
//! cycle itself (copying and erasing) is in [`crate::sim`].

use robosim_hir::TextRange;

use super::{Link, MachineCx, Unsupported};

impl MachineCx<'_, '_> {
    /// Gives the internal channel `chan` (the event `name` of a RoboSim
    /// machine, linked by `link`) its register and memory cell, once.
    pub(super) fn memory_cell(
        &mut self,
        chan: u16,
        link: &Link,
        name: &str,
        range: TextRange,
    ) -> Result<(), Unsupported> {
        if link.receivers > 1 {
            return Err(self.err(
                range,
                format!(
                    "`{name}` is sent to {} RoboSim machines or controllers: one memory cell per receiver is not \
                     supported yet (RT-22 covers one sender and one receiver)",
                    link.receivers
                ),
            ));
        }
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
