-- Jobs, their step previews and their results. A job's record is the JSON the API answers
-- (protocol/job_json.h); state, created and the lease columns repeat what queries need.
CREATE TABLE jobs (
  id text PRIMARY KEY,
  state text NOT NULL,
  record text NOT NULL,
  created double precision NOT NULL,
  scene_json text NOT NULL,
  idempotency_key text UNIQUE,
  worker text,
  lease_until timestamptz,
  attempts integer NOT NULL DEFAULT 0,
  cancel_requested boolean NOT NULL DEFAULT false,
  last_used double precision NOT NULL DEFAULT 0,
  bytes bigint NOT NULL DEFAULT 0
);
CREATE INDEX jobs_queued ON jobs (created) WHERE state = 'queued';
CREATE INDEX jobs_leases ON jobs (lease_until) WHERE state = 'running';
CREATE INDEX jobs_finished ON jobs (last_used) WHERE state NOT IN ('queued', 'running');

CREATE TABLE steps (
  job_id text NOT NULL REFERENCES jobs ON DELETE CASCADE,
  step integer NOT NULL,
  png bytea NOT NULL,
  PRIMARY KEY (job_id, step)
);

CREATE TABLE results (
  job_id text PRIMARY KEY REFERENCES jobs ON DELETE CASCADE,
  png bytea NOT NULL,
  exr bytea NOT NULL,
  solution bytea NOT NULL
);
