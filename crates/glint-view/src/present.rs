//! Showing the viewer's picture in its X11 window: the pixels go to the server as
//! `PutImage` requests on a connection of our own (x11rb, pure Rust), drawn into the
//! window winit made (window ids are the server's, so any client may draw into one).
//!
//! softbuffer did this before, but it reaches X11 through tiny-xlib, which loads
//! libX11 from a constructor at the start of every process that links it: seven shared
//! libraries before `main` (about 1 ms), in every `glint render` too, which never opens
//! a window. Here nothing of X11 runs until a window opens.

use raw_window_handle::{HasWindowHandle, RawWindowHandle};
use winit::window::Window;
use x11rb::connection::{Connection, RequestConnection};
use x11rb::protocol::xproto::{ConnectionExt, CreateGCAux, ImageFormat, ImageOrder};
use x11rb::rust_connection::RustConnection;

/// Bytes of a `PutImage` request before its pixels.
const PUT_IMAGE_HEADER: usize = 24;

/// A window's drawing connection, with what `PutImage` needs to know of the window.
pub struct Presenter {
    connection: RustConnection,
    window: u32,
    gc: u32,
    depth: u8,
    /// Whether the server wants pixels most significant byte first.
    big_endian: bool,
}

impl Presenter {
    /// Connects to the display `DISPLAY` names and prepares to draw into `window`.
    pub fn new(window: &Window) -> Result<Self, String> {
        let handle = window.window_handle().map_err(|e| e.to_string())?;
        let window = match handle.as_raw() {
            RawWindowHandle::Xlib(xlib) => xlib.window as u32,
            RawWindowHandle::Xcb(xcb) => xcb.window.get(),
            other => return Err(format!("not an X11 window ({other:?})")),
        };
        let (connection, _) = RustConnection::connect(None).map_err(|e| e.to_string())?;
        let failed = |e: &dyn std::fmt::Display| format!("X11: {e}");
        let depth = connection.get_geometry(window).map_err(|e| failed(&e))?.reply().map_err(|e| failed(&e))?.depth;
        // 32 bits a pixel, as the canvas holds them: every TrueColor visual of depth 24
        // (or 32) the servers we know of offer.
        let bits = connection.setup().pixmap_formats.iter().find(|f| f.depth == depth).map(|f| f.bits_per_pixel);
        if bits != Some(32) {
            return Err(format!("X11: the window's depth {depth} is not stored as 32-bit pixels"));
        }
        let big_endian = connection.setup().image_byte_order == ImageOrder::MSB_FIRST;
        let gc = connection.generate_id().map_err(|e| failed(&e))?;
        connection.create_gc(gc, window, &CreateGCAux::new()).map_err(|e| failed(&e))?;
        Ok(Self { connection, window, gc, depth, big_endian })
    }

    /// Draws `pixels` (0x00RRGGBB, `width` a row) at the window's top left, in bands of
    /// rows each small enough for one request.
    pub fn show(&self, pixels: &[u32], width: u32, height: u32) -> Result<(), String> {
        let failed = |e: &dyn std::fmt::Display| format!("X11: {e}");
        let row_bytes = width as usize * 4;
        let budget = self.connection.maximum_request_bytes().saturating_sub(PUT_IMAGE_HEADER);
        let rows_per_band = (budget / row_bytes.max(1)).clamp(1, u16::MAX as usize);
        let to_bytes = |p: &u32| if self.big_endian { p.to_be_bytes() } else { p.to_le_bytes() };
        let rows = pixels.chunks(width.max(1) as usize).take(height as usize);
        let mut band = Vec::with_capacity(rows_per_band * row_bytes);
        let mut top = 0;
        for band_rows in rows.collect::<Vec<_>>().chunks(rows_per_band) {
            band.clear();
            band.extend(band_rows.iter().flat_map(|row| row.iter().flat_map(to_bytes)));
            let (w, h, y) = (width as u16, band_rows.len() as u16, top as i16);
            self.connection
                .put_image(ImageFormat::Z_PIXMAP, self.window, self.gc, w, h, 0, y, 0, self.depth, &band)
                .map_err(|e| failed(&e))?;
            top += band_rows.len();
        }
        self.connection.flush().map_err(|e| failed(&e))
    }
}
