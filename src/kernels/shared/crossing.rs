gpu_struct! {
    mirrors CROSSING;
    /// One crossing of a triangle with a grid edge (thesis §3.4.2): the edge from `corner` to
    /// `corner + unit(axis)`, the triangle, where along the edge, and whether the surface is entered or
    /// exited when walking the edge towards `+axis`.
    ///
    /// Mirrors `struct GridCrossing` in `kernels/shared/crossing.wgsl`, which the rasterize kernel writes
    /// and the sweep kernel reads. Under the grid's symbolic perturbation a crossing never sits on a
    /// corner: `t` is in `[0, 1)`, and `t == 0` means "just past `corner`".
    pub struct GridCrossing {
        /// Lower corner of the grid edge.
        pub corner: [i32; 3],
        pub triangle: u32,
        /// Position along the edge, as a fraction of a cell from `corner`.
        pub t: f32,
        /// Bits 0-1: axis; bit 2: the surface is entered (winding +1) along `+axis`.
        pub flags: u32,
    }
}

/// `flags` bit saying the surface is entered.
pub const ENTER_BIT: u32 = 4;

impl GridCrossing {
    pub fn new(corner: [i32; 3], axis: usize, triangle: u32, t: f32, enter: bool) -> Self {
        Self {
            corner,
            triangle,
            t,
            flags: axis as u32 | if enter { ENTER_BIT } else { 0 },
        }
    }

    /// Axis of the grid edge (0 = x, 1 = y, 2 = z).
    pub fn axis(&self) -> usize {
        (self.flags & 3) as usize
    }

    /// Whether walking along `+axis` enters the surface (the triangle's normal points to `-axis`).
    pub fn enter(&self) -> bool {
        self.flags & ENTER_BIT != 0
    }

    /// The change of winding number across the crossing along `+axis`: `+1` entering, `-1` exiting.
    pub fn sign(&self) -> i32 {
        if self.enter() { 1 } else { -1 }
    }

    /// Index of the grid edge's lower corner along its own axis.
    pub fn along(&self) -> i32 {
        self.corner[self.axis()]
    }
}

gpu_struct! {
    mirrors CROSSING;
    /// Corners of a line from `start` on (up to the next run) have winding number `winding`.
    ///
    /// Mirrors `struct WindingRun` in `kernels/shared/crossing.wgsl`; the sweep kernel writes
    /// [`WindingRun::CONTINUES`] in the slot of a crossing that is not the last on its grid edge.
    #[derive(Eq)]
    pub struct WindingRun {
        pub start: i32,
        pub winding: i32,
    }
}

impl WindingRun {
    /// `start` of a slot that starts no run (cell indices stay far from `i32::MIN`).
    pub const CONTINUES: i32 = i32::MIN;
}
