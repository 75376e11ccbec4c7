//! `size-report ELF [ELF...]`: prints each image's sections and its flash and
//! static-RAM use against the budget (128 KiB flash, 48 KiB RAM), and exits
//! with status 1 if an image is over budget.
//!
//! Written in Rust rather than calling `size`, so CI needs neither binutils
//! nor `cargo-binutils` (`rustup component add llvm-tools` is not always
//! possible offline).

use host_tests::{FLASH_BUDGET, RAM_BUDGET, alloc_sections, usage};
use std::process::ExitCode;

fn main() -> ExitCode {
    let paths: Vec<String> = std::env::args().skip(1).collect();
    if paths.is_empty() {
        eprintln!("usage: size-report ELF [ELF...]");
        return ExitCode::from(2);
    }
    let mut ok = true;
    for path in &paths {
        let bytes = match std::fs::read(path) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("size-report: {path}: {e}");
                return ExitCode::from(2);
            }
        };
        let sections = match alloc_sections(&bytes) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("size-report: {path}: {e}");
                return ExitCode::from(2);
            }
        };
        println!("== {path}");
        for s in &sections {
            println!("  {:<16} {:#010x} {:>8}", s.name, s.addr, s.size);
        }
        let u = usage(&sections);
        let pct = |a: u64, b: u64| a as f64 * 100.0 / b as f64;
        let flash_ok = u.flash <= FLASH_BUDGET;
        let ram_ok = u.ram <= RAM_BUDGET;
        println!(
            "  flash {:>7} B ({:.1} KiB) of {} KiB budget ({:.0}%) {}",
            u.flash,
            u.flash as f64 / 1024.0,
            FLASH_BUDGET / 1024,
            pct(u.flash, FLASH_BUDGET),
            if flash_ok { "OK" } else { "OVER BUDGET" }
        );
        println!(
            "  ram   {:>7} B ({:.1} KiB) of {} KiB budget ({:.0}%) {}",
            u.ram,
            u.ram as f64 / 1024.0,
            RAM_BUDGET / 1024,
            pct(u.ram, RAM_BUDGET),
            if ram_ok { "OK" } else { "OVER BUDGET" }
        );
        ok &= flash_ok && ram_ok;
    }
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
