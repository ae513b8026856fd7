//! No-data: what is masked (NaN in the image) before anything is scored. A GRD product fills
//! the image outside its swath with zeros; such zeros are found as the zero pixels connected to
//! the image's border (a zero inside the sea, after noise removal, is data and is floored, not
//! masked). The user's `--exclude` raster is read in [`crate::exclude`].

use ndarray::Array2;
use std::collections::VecDeque;

/// Mark as masked (true) every pixel of `raw` equal to zero that is connected (4-neighbours)
/// to the image's border through zeros; returns how many.
pub fn border_zeros(raw: &Array2<f32>, masked: &mut Array2<bool>) -> usize {
    let (h, w) = raw.dim();
    let mut queue = VecDeque::new();
    let mut count = 0;
    let mut visit = |r: usize, c: usize, masked: &mut Array2<bool>, queue: &mut VecDeque<(usize, usize)>| {
        if raw[[r, c]] == 0.0 && !masked[[r, c]] {
            masked[[r, c]] = true;
            queue.push_back((r, c));
            count += 1;
        }
    };
    for r in 0..h {
        visit(r, 0, masked, &mut queue);
        visit(r, w - 1, masked, &mut queue);
    }
    for c in 0..w {
        visit(0, c, masked, &mut queue);
        visit(h - 1, c, masked, &mut queue);
    }
    while let Some((r, c)) = queue.pop_front() {
        if r > 0 {
            visit(r - 1, c, masked, &mut queue);
        }
        if r + 1 < h {
            visit(r + 1, c, masked, &mut queue);
        }
        if c > 0 {
            visit(r, c - 1, masked, &mut queue);
        }
        if c + 1 < w {
            visit(r, c + 1, masked, &mut queue);
        }
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    #[test]
    fn only_zeros_reaching_the_border_are_no_data() {
        // a border of zeros on the left, a zero island inside the data
        let raw = array![
            [0.0f32, 0.0, 5.0, 6.0, 7.0],
            [0.0, 3.0, 0.0, 6.0, 7.0],
            [0.0, 0.0, 5.0, 6.0, 7.0],
        ];
        let mut masked = Array2::from_elem(raw.dim(), false);
        assert_eq!(border_zeros(&raw, &mut masked), 5);
        assert!(masked[[0, 0]] && masked[[0, 1]] && masked[[2, 1]]);
        assert!(!masked[[1, 2]], "the inner zero is data");
        assert!(!masked[[1, 1]]);
    }
}
