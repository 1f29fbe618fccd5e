# The real single-node Slurm test (scripts/ci_slurm_test.sh): job array of 4 shards, merge job,
# killed and resubmitted shard. Label `slurm`; exit 77 (no Slurm and not root) is a skip.
add_test(NAME slurm_job_array_test
  COMMAND bash ${PROJECT_SOURCE_DIR}/scripts/ci_slurm_test.sh $<TARGET_FILE:fogpipe>)
set_tests_properties(slurm_job_array_test PROPERTIES
  LABELS "slurm;integration" TIMEOUT 600 RUN_SERIAL TRUE SKIP_RETURN_CODE 77)
