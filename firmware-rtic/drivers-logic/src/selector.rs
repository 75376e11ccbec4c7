//! The 16-position rotary selector (SEL0..SEL3, active-high with pull-downs).

/// Selector value from the four input levels: SEL0 + 2·SEL1 + 4·SEL2 + 8·SEL3.
pub const fn decode(sel: [bool; 4]) -> u8 {
    sel[0] as u8 | (sel[1] as u8) << 1 | (sel[2] as u8) << 2 | (sel[3] as u8) << 3
}

/// What the firmware does after power-on, chosen by the selector.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BootMode {
    /// Position 0: calibrate the ground sensors (seed §2.3).
    Calibrate,
    /// Any other position: explore; the position is the robot's id hint.
    Run(u8),
}

impl BootMode {
    /// The mode for a selector value read at power-on.
    pub const fn from_selector(value: u8) -> Self {
        match value & 0x0F {
            0 => BootMode::Calibrate,
            v => BootMode::Run(v),
        }
    }
}

/// The `selector=N` setting (N in 0..=15) in an emulator command line such
/// as QEMU's `-kernel` path followed by its `-append` text, so that several
/// emulated robots can have different ids and selector 0 can be tried.
pub fn from_cmdline(cmdline: &[u8]) -> Option<u8> {
    cmdline_value(cmdline, b"selector")
        .and_then(|v| u8::try_from(v).ok())
        .filter(|&v| v <= 15)
}

/// The decimal value of the first `key=N` word in an emulator command line
/// (the emulated board also reads its link nonce this way, so that the host
/// can give every run a fresh session).
pub fn cmdline_value(cmdline: &[u8], key: &[u8]) -> Option<u32> {
    cmdline
        .split(|&b| b == b' ' || b == 0)
        .filter_map(|word| word.strip_prefix(key)?.strip_prefix(b"="))
        .find_map(|v| core::str::from_utf8(v).ok()?.parse::<u32>().ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decode_weights() {
        assert_eq!(decode([false; 4]), 0);
        assert_eq!(decode([true, false, false, false]), 1);
        assert_eq!(decode([false, true, true, false]), 6);
        assert_eq!(decode([true; 4]), 15);
    }

    #[test]
    fn cmdline() {
        assert_eq!(from_cmdline(b"fw.elf selector=3"), Some(3));
        assert_eq!(from_cmdline(b"fw.elf foo selector=0 bar"), Some(0));
        assert_eq!(from_cmdline(b"fw.elf selector=16"), None);
        assert_eq!(from_cmdline(b"fw.elf selector=x"), None);
        assert_eq!(from_cmdline(b"fw.elf"), None);
        assert_eq!(from_cmdline(b""), None);
        assert_eq!(from_cmdline(b"fw.elf selector=300"), None);
    }

    #[test]
    fn cmdline_values() {
        let line = b"fw.elf selector=2 nonce=4000000000 nonces=7";
        assert_eq!(cmdline_value(line, b"nonce"), Some(4_000_000_000));
        assert_eq!(cmdline_value(line, b"selector"), Some(2));
        assert_eq!(cmdline_value(b"fw.elf nonce=-1", b"nonce"), None);
        assert_eq!(cmdline_value(b"fw.elf nonces=7", b"nonce"), None);
    }

    #[test]
    fn zero_calibrates() {
        assert_eq!(BootMode::from_selector(0), BootMode::Calibrate);
        assert_eq!(BootMode::from_selector(3), BootMode::Run(3));
        assert_eq!(BootMode::from_selector(0x10), BootMode::Calibrate);
    }
}
