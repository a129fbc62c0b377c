//! Values on a grid that state their storage order.
//!
//! Photos and masks are stored row by row; the rain's wall is stored column
//! by column, because water runs down. A [`Field`] carries its order in its
//! type ([`RowMajor`] or [`ColumnMajor`]), so a column-major deposit cannot
//! be passed where a row-major map is expected. Inner loops still work on
//! the plain slice ([`Field::data`]); the order says how to read it.

use std::marker::PhantomData;

/// A storage order: where pixel (x, y) of a `width` x `height` grid lives.
pub trait Order: Copy + Default + std::fmt::Debug + Send + Sync + 'static {
    /// Storage index of (x, y).
    fn index(width: usize, height: usize, x: usize, y: usize) -> usize;
    /// The pixel (x, y) at storage index `i`.
    fn position(width: usize, height: usize, i: usize) -> (usize, usize);
    /// Length of one contiguous line: a row's width or a column's height.
    fn line(width: usize, height: usize) -> usize;
}

/// Row by row: (x, y) at `y * width + x`; lines are rows.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Rows;

/// Column by column: (x, y) at `x * height + y`; lines are columns.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Columns;

impl Order for Rows {
    #[inline(always)]
    fn index(width: usize, _: usize, x: usize, y: usize) -> usize {
        y * width + x
    }
    fn position(width: usize, _: usize, i: usize) -> (usize, usize) {
        (i % width, i / width)
    }
    fn line(width: usize, _: usize) -> usize {
        width
    }
}

impl Order for Columns {
    #[inline(always)]
    fn index(_: usize, height: usize, x: usize, y: usize) -> usize {
        x * height + y
    }
    fn position(_: usize, height: usize, i: usize) -> (usize, usize) {
        (i / height, i % height)
    }
    fn line(_: usize, height: usize) -> usize {
        height
    }
}

/// `width` x `height` values stored in order `O`.
#[derive(Debug, Clone, PartialEq)]
pub struct Field<T, O: Order> {
    width: usize,
    height: usize,
    data: Vec<T>,
    order: PhantomData<O>,
}

/// A field stored row by row (photos, masks, the grid's luminance).
pub type RowMajor<T> = Field<T, Rows>;

/// A field stored column by column (the rain's wall and deposits).
pub type ColumnMajor<T> = Field<T, Columns>;

impl<T, O: Order> Field<T, O> {
    /// A field over `data`, which is in order `O`.
    ///
    /// # Panics
    /// When `data` does not hold `width * height` values (a caller's bug,
    /// never user input).
    pub fn new(width: usize, height: usize, data: Vec<T>) -> Self {
        assert_eq!(data.len(), width * height, "{width} x {height} field");
        Field {
            width,
            height,
            data,
            order: PhantomData,
        }
    }

    /// Every value `value`.
    pub fn filled(width: usize, height: usize, value: T) -> Self
    where
        T: Clone,
    {
        Self::new(width, height, vec![value; width * height])
    }

    /// `f(x, y)` at every pixel.
    pub fn from_fn(width: usize, height: usize, f: impl Fn(usize, usize) -> T) -> Self {
        let data = (0..width * height)
            .map(|i| {
                let (x, y) = O::position(width, height, i);
                f(x, y)
            })
            .collect();
        Self::new(width, height, data)
    }

    /// Grid width.
    #[inline]
    pub fn width(&self) -> usize {
        self.width
    }

    /// Grid height.
    #[inline]
    pub fn height(&self) -> usize {
        self.height
    }

    /// Storage index of (x, y).
    #[inline(always)]
    pub fn index(&self, x: usize, y: usize) -> usize {
        O::index(self.width, self.height, x, y)
    }

    /// The value at (x, y).
    #[inline(always)]
    pub fn get(&self, x: usize, y: usize) -> T
    where
        T: Copy,
    {
        self.data[self.index(x, y)]
    }

    /// The values in storage order.
    #[inline]
    pub fn data(&self) -> &[T] {
        &self.data
    }

    /// The values in storage order, to write.
    #[inline]
    pub fn data_mut(&mut self) -> &mut [T] {
        &mut self.data
    }

    /// Length of a contiguous line: the width for [`RowMajor`], the height
    /// for [`ColumnMajor`].
    #[inline]
    pub fn line(&self) -> usize {
        O::line(self.width, self.height)
    }

    /// Whether `other` covers the same grid.
    pub fn same_size<U, P: Order>(&self, other: &Field<U, P>) -> bool {
        (self.width, self.height) == (other.width, other.height)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orders_place_pixels_where_they_say() {
        let rows = RowMajor::from_fn(3, 2, |x, y| 10 * y + x);
        let cols = ColumnMajor::from_fn(3, 2, |x, y| 10 * y + x);
        assert_eq!(rows.data(), [0, 1, 2, 10, 11, 12]);
        assert_eq!(cols.data(), [0, 10, 1, 11, 2, 12]);
        assert_eq!((rows.line(), cols.line()), (3, 2));
        for y in 0..2 {
            for x in 0..3 {
                assert_eq!(rows.get(x, y), cols.get(x, y));
            }
        }
        assert!(rows.same_size(&cols));
    }

    #[test]
    #[should_panic(expected = "3 x 2 field")]
    fn new_refuses_a_wrong_length() {
        let _ = RowMajor::new(3, 2, vec![0.0; 5]);
    }
}
