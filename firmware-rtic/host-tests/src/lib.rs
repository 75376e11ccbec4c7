//! Host-side tools for the e-puck2 firmware: the ELF size report used by CI
//! to enforce the memory budget, and (in `tests/`) the QEMU boot-and-talk test.

#![deny(missing_docs)]

/// Flash budget from the issue: 128 KiB.
pub const FLASH_BUDGET: u64 = 128 * 1024;
/// Static RAM budget from the issue: 48 KiB (map included, stack excluded).
pub const RAM_BUDGET: u64 = 48 * 1024;

/// One allocated section of the image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Section {
    /// Section name.
    pub name: String,
    /// Run-time address.
    pub addr: u64,
    /// Size in bytes.
    pub size: u64,
    /// Whether the ELF holds its contents (false for .bss-like sections).
    pub has_bits: bool,
}

/// Flash and static RAM use of an image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Usage {
    /// Bytes programmed into flash (code, constants, initial values of .data).
    pub flash: u64,
    /// Bytes of RAM reserved statically (.data, .bss, .uninit).
    pub ram: u64,
}

/// Whether `addr` lies in SRAM (0x2000_0000..) or CCM RAM (0x1000_0000..).
fn in_ram(addr: u64) -> bool {
    (0x2000_0000..0x2010_0000).contains(&addr) || (0x1000_0000..0x1001_0000).contains(&addr)
}

/// Sums the allocated sections the way `size` does: a section in RAM costs
/// RAM, plus flash for its initial contents if it has any; a section
/// elsewhere (flash) costs flash.
pub fn usage(sections: &[Section]) -> Usage {
    let mut u = Usage::default();
    for s in sections {
        if in_ram(s.addr) {
            u.ram += s.size;
            if s.has_bits {
                u.flash += s.size;
            }
        } else {
            u.flash += s.size;
        }
    }
    u
}

/// The allocated (SHF_ALLOC) sections of a 32-bit little-endian ELF file.
pub fn alloc_sections(elf: &[u8]) -> Result<Vec<Section>, String> {
    let u16_at = |o: usize| -> Result<u64, String> {
        elf.get(o..o + 2)
            .map(|b| u16::from_le_bytes([b[0], b[1]]) as u64)
            .ok_or_else(|| format!("truncated at {o}"))
    };
    let u32_at = |o: usize| -> Result<u64, String> {
        elf.get(o..o + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64)
            .ok_or_else(|| format!("truncated at {o}"))
    };
    if elf.get(0..4) != Some(b"\x7fELF".as_slice())
        || elf.get(4) != Some(&1)
        || elf.get(5) != Some(&1)
    {
        return Err("not a 32-bit little-endian ELF".into());
    }
    let shoff = u32_at(0x20)? as usize;
    let shentsize = u16_at(0x2E)? as usize;
    let shnum = u16_at(0x30)? as usize;
    let shstrndx = u16_at(0x32)? as usize;
    let sh = |i: usize| shoff + i * shentsize;
    let strtab = u32_at(sh(shstrndx) + 0x10)? as usize;
    let mut out = Vec::new();
    for i in 0..shnum {
        let base = sh(i);
        let (name_off, kind, flags) =
            (u32_at(base)? as usize, u32_at(base + 4)?, u32_at(base + 8)?);
        const SHF_ALLOC: u64 = 2;
        const SHT_NOBITS: u64 = 8;
        let size = u32_at(base + 0x14)?;
        if flags & SHF_ALLOC == 0 || size == 0 {
            continue;
        }
        let name_bytes = elf.get(strtab + name_off..).ok_or("bad section name")?;
        let end = name_bytes
            .iter()
            .position(|&b| b == 0)
            .unwrap_or(name_bytes.len());
        out.push(Section {
            name: String::from_utf8_lossy(&name_bytes[..end]).into_owned(),
            addr: u32_at(base + 0x0C)?,
            size,
            has_bits: kind != SHT_NOBITS,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(name: &str, addr: u64, size: u64, has_bits: bool) -> Section {
        Section {
            name: name.into(),
            addr,
            size,
            has_bits,
        }
    }

    #[test]
    fn data_costs_flash_and_ram_bss_only_ram() {
        let u = usage(&[
            s(".vector_table", 0x0800_0000, 392, true),
            s(".text", 0x0800_0188, 1000, true),
            s(".data", 0x2000_0000, 56, true),
            s(".bss", 0x2000_0038, 100, false),
            s(".uninit", 0x2000_0100, 1024, false),
        ]);
        assert_eq!(
            u,
            Usage {
                flash: 392 + 1000 + 56,
                ram: 56 + 100 + 1024
            }
        );
    }

    #[test]
    fn rejects_non_elf() {
        assert!(alloc_sections(b"hello").is_err());
    }
}
