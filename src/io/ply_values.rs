//! Decoders for the PLY body: one for ASCII, one per binary byte order. Both hand out values one
//! property at a time as f64 (exact for every PLY type), so one element walk serves all three
//! encodings.

use super::error::Location;
use super::ply_header::Scalar;

/// Why a value could not be produced; the caller adds the file and the location.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Fault {
    /// The body ends before the element's records do.
    Truncated,
    NotANumber(String),
    /// An integer that the declared type cannot hold.
    OutOfRange(String, Scalar),
    /// An ASCII record line with fewer values than the element declares.
    MissingValue,
    /// An ASCII record line with more values than the element declares.
    ExtraValues,
}

pub(crate) trait Values {
    /// Starts the next record.
    fn begin(&mut self) -> Result<(), Fault>;
    /// The next value of the current record.
    fn value(&mut self, ty: Scalar) -> Result<f64, Fault>;
    /// Fails unless `count` values of type `ty` can still follow: bounds list lengths before any
    /// work is done for them.
    fn check_list(&self, count: usize, ty: Scalar) -> Result<(), Fault>;
    /// Ends the current record.
    fn end(&mut self) -> Result<(), Fault>;
    /// Where record `index` of `element` is, for messages.
    fn location(&self, element: &str, index: usize) -> Location;
    /// An upper bound on the records of `min_size` bytes that remain, for sizing allocations.
    fn max_records(&self, min_size: usize) -> usize;
}

/// Binary body, little-endian (`BIG = false`) or big-endian.
pub(crate) struct Binary<'a, const BIG: bool> {
    data: &'a [u8],
    pos: usize,
}

impl<'a, const BIG: bool> Binary<'a, BIG> {
    pub(crate) fn new(data: &'a [u8]) -> Self {
        Self { data, pos: 0 }
    }
}

impl<const BIG: bool> Values for Binary<'_, BIG> {
    fn begin(&mut self) -> Result<(), Fault> {
        Ok(())
    }

    #[inline(always)]
    fn value(&mut self, ty: Scalar) -> Result<f64, Fault> {
        let size = ty.size();
        let bytes = self
            .data
            .get(self.pos..self.pos + size)
            .ok_or(Fault::Truncated)?;
        self.pos += size;
        Ok(ty.decode(bytes, BIG))
    }

    fn check_list(&self, count: usize, ty: Scalar) -> Result<(), Fault> {
        match count.checked_mul(ty.size()) {
            Some(len) if len <= self.data.len() - self.pos => Ok(()),
            _ => Err(Fault::Truncated),
        }
    }

    fn end(&mut self) -> Result<(), Fault> {
        Ok(())
    }

    fn location(&self, element: &str, index: usize) -> Location {
        Location::Element {
            element: element.to_string(),
            index,
        }
    }

    fn max_records(&self, min_size: usize) -> usize {
        (self.data.len() - self.pos) / min_size.max(1)
    }
}

/// ASCII body: one record per line (blank lines are skipped), values separated by whitespace.
pub(crate) struct Ascii<'a> {
    data: &'a [u8],
    /// Start of the unread part of the current line.
    pos: usize,
    /// End of the current line (index of its `\n`, or the end of the data).
    line_end: usize,
    /// Start of the next line.
    next: usize,
    /// 1-based number of the current line.
    line: usize,
}

impl<'a> Ascii<'a> {
    /// `first_line` is the number of the body's first line.
    pub(crate) fn new(data: &'a [u8], first_line: usize) -> Self {
        Self {
            data,
            pos: 0,
            line_end: 0,
            next: 0,
            line: first_line.saturating_sub(1),
        }
    }

    fn skip_blanks(&mut self) {
        while self.pos < self.line_end && self.data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }
}

impl Values for Ascii<'_> {
    fn begin(&mut self) -> Result<(), Fault> {
        loop {
            if self.next >= self.data.len() {
                return Err(Fault::Truncated);
            }
            let start = self.next;
            self.line_end = self.data[start..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(self.data.len(), |len| start + len);
            self.next = self.line_end + 1;
            self.pos = start;
            self.line += 1;
            self.skip_blanks();
            if self.pos < self.line_end {
                return Ok(());
            }
        }
    }

    #[inline]
    fn value(&mut self, ty: Scalar) -> Result<f64, Fault> {
        self.skip_blanks();
        let start = self.pos;
        while self.pos < self.line_end && !self.data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if start == self.pos {
            return Err(Fault::MissingValue);
        }
        let token = &self.data[start..self.pos];
        let text = || String::from_utf8_lossy(token).into_owned();
        let token = std::str::from_utf8(token).map_err(|_| Fault::NotANumber(text()))?;
        match ty {
            Scalar::F32 => token
                .parse::<f32>()
                .map(f64::from)
                .map_err(|_| Fault::NotANumber(text())),
            Scalar::F64 => token.parse::<f64>().map_err(|_| Fault::NotANumber(text())),
            _ => {
                let value = token
                    .parse::<i64>()
                    .map_err(|_| Fault::NotANumber(text()))?;
                let (lo, hi) = ty.integer_range();
                let value = value as f64;
                if value < lo || value > hi {
                    return Err(Fault::OutOfRange(text(), ty));
                }
                Ok(value)
            }
        }
    }

    fn check_list(&self, count: usize, _ty: Scalar) -> Result<(), Fault> {
        // Every value needs at least one character on the line.
        if count <= self.line_end - self.pos {
            Ok(())
        } else {
            Err(Fault::MissingValue)
        }
    }

    fn end(&mut self) -> Result<(), Fault> {
        self.skip_blanks();
        if self.pos < self.line_end {
            return Err(Fault::ExtraValues);
        }
        Ok(())
    }

    fn location(&self, _element: &str, _index: usize) -> Location {
        Location::Line(self.line)
    }

    fn max_records(&self, min_size: usize) -> usize {
        (self.data.len() - self.pos) / min_size.max(1)
    }
}
