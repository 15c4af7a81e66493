//! Program summary: counts, lengths, bounding box, machining time.
