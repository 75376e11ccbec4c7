//! USART3 (PD8 TX, PD9 RX, AF7) to the ESP32, which relays it over Bluetooth
//! SPP ("UART" service); 115200 8N1, no flow control.
//!
//! Interrupt-driven ring buffers: the USART interrupt moves each received
//! byte into an `rtic_sync` channel (the receive ring the link task awaits)
//! and drains a `heapless` SPSC queue (the transmit ring) while TXE is set.
//! The link task enqueues whole frames (already COBS-encoded by core-algo's
//! link layer) and pends the interrupt to start transmission, so it never
//! touches the peripheral. The same rings serve the emulated board's body
//! channel on USART2 (generic over the USART). The F4 USART has no
//! FIFO, so this interrupt runs above every task that may block (sampling
//! does ADC conversions, control a ~1 ms I2C read).

use heapless::spsc::{Consumer, Producer, Queue};
use rtic_sync::channel::{Receiver, Sender};
use stm32f4xx_hal::{
    pac::Interrupt,
    prelude::*,
    serial::{Instance, Rx, Tx},
};

/// Receive ring size (bytes): a few frames, 11 ms of traffic at 115200 baud
/// (`rtic_sync` channels hold at most 255).
pub const RX_CAPACITY: usize = 128;
/// Transmit ring size (bytes); `heapless` queues hold one less.
pub const TX_CAPACITY: usize = 512;

/// The transmit ring's storage (lives in a `static` owned by `init`).
pub type TxQueue = Queue<u8, TX_CAPACITY>;
/// Producer side of the receive ring, held by the interrupt.
pub type RxSender = Sender<'static, u8, RX_CAPACITY>;
/// Consumer side of the receive ring, held by the link task.
pub type RxReceiver = Receiver<'static, u8, RX_CAPACITY>;

/// The interrupt half: owns the peripheral.
pub struct LinkIsr<U: Instance> {
    rx: Rx<U>,
    tx: Tx<U>,
    rx_bytes: RxSender,
    tx_bytes: Consumer<'static, u8>,
    /// Bytes lost to a full receive ring or a USART error (overrun, framing).
    pub rx_lost: u32,
}

impl<U: Instance> LinkIsr<U> {
    /// Takes the split serial port (receiver already listening) and the rings.
    pub fn new(rx: Rx<U>, tx: Tx<U>, rx_bytes: RxSender, tx_bytes: Consumer<'static, u8>) -> Self {
        LinkIsr {
            rx,
            tx,
            rx_bytes,
            tx_bytes,
            rx_lost: 0,
        }
    }

    /// USART interrupt body: one received byte in, as many bytes out as TXE allows.
    pub fn on_interrupt(&mut self) {
        if self.rx.is_rx_not_empty() {
            match self.rx.read() {
                Ok(b) => {
                    if self.rx_bytes.try_send(b).is_err() {
                        self.rx_lost = self.rx_lost.wrapping_add(1);
                    }
                }
                Err(_) => self.rx_lost = self.rx_lost.wrapping_add(1),
            }
        }
        while self.tx.is_tx_empty() {
            match self.tx_bytes.dequeue() {
                Some(b) => {
                    let _ = self.tx.write(b);
                }
                None => break,
            }
        }
        if self.tx_bytes.ready() {
            self.tx.listen();
        } else {
            self.tx.unlisten();
        }
    }
}

/// The task half: queues whole frames for transmission.
pub struct LinkTx {
    queue: Producer<'static, u8>,
    irq: Interrupt,
}

impl LinkTx {
    /// Wraps the transmit ring's producer; `irq` is the USART's interrupt,
    /// pended to start a transmission.
    pub fn new(queue: Producer<'static, u8>, irq: Interrupt) -> Self {
        LinkTx { queue, irq }
    }

    /// Free bytes in the ring.
    pub fn room(&self) -> usize {
        self.queue.capacity() - self.queue.len()
    }

    /// Queues `bytes` (one encoded frame or line) whole; `false` (dropped
    /// whole) if the ring lacks room, so the receiver never sees half a
    /// frame.
    pub fn send(&mut self, bytes: &[u8]) -> bool {
        if self.room() < bytes.len() {
            return false;
        }
        for &b in bytes {
            let _ = self.queue.enqueue(b);
        }
        rtic::pend(self.irq);
        true
    }

    /// Whether everything queued has been handed to the USART.
    pub fn is_idle(&self) -> bool {
        self.queue.is_empty()
    }
}
