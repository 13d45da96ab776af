#include "dataset/gaussian_cloud.h"
