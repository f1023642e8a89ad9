//! A column of fixed-size values that is either owned or borrowed from a memory map.

use std::sync::Arc;

use bytemuck::Pod;
use memmap2::Mmap;

/// Values of one kind for every row (vectors, ids, tag codes).
///
/// An index opened from a file borrows its columns from the file's memory map, so opening
/// costs no copy; the first change to the index turns every column into an owned `Vec`.
#[derive(Debug)]
pub(crate) enum Column<T: Pod> {
    Owned(Vec<T>),
    Mapped {
        map: Arc<Mmap>,
        /// Byte offset of the first value in the map; a multiple of `align_of::<T>()`,
        /// checked when the file was opened.
        start: usize,
        /// Number of values.
        len: usize,
    },
}

impl<T: Pod> Column<T> {
    pub(crate) fn as_slice(&self) -> &[T] {
        match self {
            Column::Owned(values) => values,
            Column::Mapped { map, start, len } => map
                .get(*start..start + len * size_of::<T>())
                .and_then(|bytes| bytemuck::try_cast_slice(bytes).ok())
                // Unreachable: the range and alignment were validated on open.
                .unwrap_or(&[]),
        }
    }

    pub(crate) fn to_mut(&mut self) -> &mut Vec<T> {
        if let Column::Mapped { .. } = self {
            *self = Column::Owned(self.as_slice().to_vec());
        }
        match self {
            Column::Owned(values) => values,
            // Unreachable: the column was made owned just above.
            Column::Mapped { .. } => {
                *self = Column::Owned(Vec::new());
                self.to_mut()
            }
        }
    }

    pub(crate) fn is_mapped(&self) -> bool {
        matches!(self, Column::Mapped { .. })
    }
}
