//! Showing the viewer's picture in its X11 window: the pixels go to the server as
//! `PutImage` requests on a connection of our own (x11rb, pure Rust), drawn into the
//! window winit made (window ids are the server's, so any client may draw into one).
//!
//! softbuffer did this before, but it reaches X11 through tiny-xlib, which loads
//! libX11 from a constructor at the start of every process that links it: seven shared
//! libraries before `main` (about 1 ms), in every `glint render` too, which never opens
//! a window. Here nothing of X11 runs until a window opens.

use std::cell::RefCell;

use raw_window_handle::{HasWindowHandle, RawWindowHandle};
use winit::window::Window;
use x11rb::connection::{Connection, RequestConnection};
use x11rb::protocol::xproto::{ConnectionExt, CreateGCAux, ImageFormat, ImageOrder, VisualClass};
use x11rb::rust_connection::RustConnection;

/// Bytes of a `PutImage` request before its pixels, with the four of the length field
/// that BIG-REQUESTS adds (x11rb compares the size without them to its maximum).
const PUT_IMAGE_HEADER: usize = 28;

/// A window's drawing connection, with what `PutImage` needs to know of the window.
pub struct Presenter {
    connection: RustConnection,
    window: u32,
    gc: u32,
    depth: u8,
    /// Set in every pixel: the alpha byte of a 32-bit visual, which a compositor would
    /// otherwise show as transparent.
    opaque: u32,
    /// Whether the server wants pixels most significant byte first.
    big_endian: bool,
    /// One band of rows in the server's byte order, kept from frame to frame.
    band: RefCell<Vec<u8>>,
}

impl Presenter {
    /// Connects to the display `DISPLAY` names and prepares to draw into `window`,
    /// whose visual must be 8-bit TrueColor (as winit's windows are).
    pub fn new(window: &Window) -> Result<Self, String> {
        let handle = window.window_handle().map_err(|e| e.to_string())?;
        let window = match handle.as_raw() {
            RawWindowHandle::Xlib(xlib) => xlib.window as u32,
            RawWindowHandle::Xcb(xcb) => xcb.window.get(),
            other => return Err(format!("not an X11 window ({other:?})")),
        };
        let (connection, _) = RustConnection::connect(None).map_err(|e| e.to_string())?;
        connection.prefetch_maximum_request_bytes();
        let failed = |e: &dyn std::fmt::Display| format!("X11: {e}");
        let visual = connection.get_window_attributes(window).map_err(|e| failed(&e))?;
        let visual = visual.reply().map_err(|e| failed(&e))?.visual;
        let depth = true_color_depth(&connection, visual)?;
        let big_endian = connection.setup().image_byte_order == ImageOrder::MSB_FIRST;
        let gc = connection.generate_id().map_err(|e| failed(&e))?;
        connection.create_gc(gc, window, &CreateGCAux::new()).map_err(|e| failed(&e))?;
        let opaque = if depth == 32 { 0xFF00_0000 } else { 0 };
        Ok(Self { connection, window, gc, depth, opaque, big_endian, band: RefCell::default() })
    }

    /// Draws `pixels` (0x00RRGGBB, `width` a row, `height` rows) at the window's top
    /// left, in bands of rows each small enough for one request, then reads whatever the
    /// server sent back (errors, mapping notices), which would otherwise pile up.
    pub fn show(&self, pixels: &[u32], width: u32, height: u32) -> Result<(), String> {
        let failed = |e: &dyn std::fmt::Display| format!("X11: {e}");
        let (Ok(w), Ok(h)) = (u16::try_from(width), i16::try_from(height)) else {
            return Err(format!("X11: a {width}×{height} picture is larger than a window can be"));
        };
        let row = width as usize;
        let Some(pixels) = pixels.get(..row * h as usize) else {
            return Err(format!("{} pixels are not a {width}×{height} picture", pixels.len()));
        };
        if pixels.is_empty() {
            return Ok(());
        }
        let budget = self.connection.maximum_request_bytes().saturating_sub(PUT_IMAGE_HEADER);
        let rows_per_band = (budget / (4 * row).max(1)).max(1);
        let mut band = self.band.borrow_mut();
        for (index, rows) in pixels.chunks(rows_per_band * row).enumerate() {
            band.clear();
            band.extend(rows.iter().flat_map(|&p| self.bytes(p | self.opaque)));
            let top = (index * rows_per_band) as i16;
            let count = (rows.len() / row) as u16;
            self.connection
                .put_image(ImageFormat::Z_PIXMAP, self.window, self.gc, w, count, 0, top, 0, self.depth, &band)
                .map_err(|e| failed(&e))?;
        }
        self.connection.flush().map_err(|e| failed(&e))?;
        while self.connection.poll_for_event().map_err(|e| failed(&e))?.is_some() {}
        Ok(())
    }

    /// A pixel as the server orders its bytes.
    fn bytes(&self, pixel: u32) -> [u8; 4] {
        if self.big_endian { pixel.to_be_bytes() } else { pixel.to_le_bytes() }
    }
}

/// The depth of `visual` if it is TrueColor with 8 bits a channel stored as 32-bit
/// pixels (red in the high byte, as the canvas has it); an error naming it otherwise.
fn true_color_depth(connection: &RustConnection, visual: u32) -> Result<u8, String> {
    let setup = connection.setup();
    let found = setup
        .roots
        .iter()
        .flat_map(|screen| &screen.allowed_depths)
        .find_map(|depth| depth.visuals.iter().find(|v| v.visual_id == visual).map(|v| (depth.depth, v)));
    let Some((depth, v)) = found else { return Err(format!("X11: the window's visual {visual:#x} is unknown")) };
    let stored = setup.pixmap_formats.iter().find(|f| f.depth == depth).map(|f| f.bits_per_pixel);
    let masks = (v.red_mask, v.green_mask, v.blue_mask);
    if v.class != VisualClass::TRUE_COLOR || masks != (0xFF_0000, 0xFF00, 0xFF) || stored != Some(32) {
        return Err(format!(
            "X11: the window's visual (depth {depth}, class {:?}, masks {masks:x?}) is not 8-bit TrueColor",
            v.class
        ));
    }
    Ok(depth)
}
