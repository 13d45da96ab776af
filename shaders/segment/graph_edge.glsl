// An entry of the symmetric adjacency (see GraphEdgesPush): its kNN slot and the other node.
#ifndef PG_GRAPH_EDGE_GLSL
#define PG_GRAPH_EDGE_GLSL
uint edge_slot(uint e, uint half_) { return e < half_ ? e : e - half_; }
// The column of entry e (requires Nbr bound as nbr[] and k).
#define EDGE_COLUMN(e, half_, k) ((e) < (half_) ? nbr[(e)] : ((e) - (half_)) / (k))
#endif
