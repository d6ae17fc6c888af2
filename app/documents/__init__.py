"""The PDF's machinery: A4 layout, the embedded Noto Sans, the LSF chart, the stamp of a lapsed paper."""
