/* pfnn_private.h (private) - what the controller needs from the network beyond the public API. */
#ifndef MM_PFNN_PRIVATE_H
#define MM_PFNN_PRIVATE_H

#include <mm/pfnn.h>

/* The output mean (MM_PFNN_OUTPUT_DIM floats): the demo's initial pose. */
const float *mm__pfnn_network_ymean(const mm_pfnn_network *net);

#endif
